#pragma once
/// \file t_junctions.h
/// T-junctions: a vertex of one triangle lying on a boundary edge of another, the crack left
/// between parts of one surface that were meshed separately (a CAD body exported face by face, a
/// scan whose stitched parts were remeshed on one side of the seam). Apart, the two sides are
/// boundaries and each part fits as an open sheet; closing the junctions joins them.
///
/// Decision (docs/robustness.md "T-junctions are closed"): the triangle whose boundary edge holds
/// the vertices is split at them (no vertex is moved or added, so the working copy's map to the
/// layer's vertices is unchanged), after which the two sides share their edges. MeshLab's
/// Snap Mismatched Borders does the same in its cleaning plugin (moving the vertex onto the edge);
/// vcglib has no such function, and the working copy is index arrays (input_prep.h says why).
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Splits, for every boundary side in `boundarySides` (face * 3 + k: the edge F[f][k] ->
/// F[f][k+1] has only this face), the face at every vertex of another boundary side that lies
/// within `tol` of the edge and more than `tol` from both its ends. A face with such vertices on
/// several of its sides is triangulated with all of them (no triangle of three collinear
/// vertices). The new faces keep the face's orientation; the other faces keep their order, the
/// split ones' pieces are appended. Returns how many vertices were inserted into edges (0: `F`
/// unchanged). Cost O(boundary length / mean boundary edge) grid look-ups.
int CloseTJunctions(const std::vector<Vec3>& V, std::vector<Tri>& F, const std::vector<int>& boundarySides, double tol);

}  // namespace vcgext
