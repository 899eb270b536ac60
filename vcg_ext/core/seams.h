#pragma once
/// \file seams.h
/// Seams between parts of one surface that were meshed separately (a CAD body exported face by
/// face, a scan whose stitched parts were remeshed on one side of the seam): the two sides' vertices
/// are near-coincident copies (each part computed its own) or T-junctions (a vertex of one triangle
/// lying on a boundary edge of another). Apart, both sides are boundaries and each part fits as an
/// open sheet; welding the copies and closing the junctions joins them.
///
/// Decision (docs/robustness.md "Seams are closed"): copies are merged like duplicates (the layer's
/// vertices map to the kept one), and the triangle whose boundary edge holds T-junction vertices
/// is split at them (no vertex is moved or added, so the working copy's map to the layer's vertices
/// stays what it is), after which the two sides share their edges. MeshLab's Snap Mismatched
/// Borders does the T-junction part in its cleaning plugin (moving the vertex onto the edge);
/// vcglib has no such function, and the working copy is index arrays (input_prep.h says why).
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Merges each vertex of a boundary side (the ends of `boundarySides`, face * 3 + k: the edge
/// F[f][k] -> F[f][k+1] has only this face) into the first such vertex within `tol` that is kept
/// and shares no edge with it. `into` (resized to V.size()): each vertex's representative. Returns
/// how many were merged (0, `into` the identity, if a face would lose a corner).
int WeldSeamVertices(const std::vector<Vec3>& V, const std::vector<Tri>& F, const std::vector<int>& boundarySides,
                     double tol, std::vector<int>& into);

/// Cracks: how many ends of `boundarySides` have another such end that shares no edge with them,
/// closer than `share` times the shorter of the two's shortest boundary sides and than `share`
/// times the median boundary side (`reach`), but not at the same position (exactly coincident ends
/// are vertices the working copy keeps apart on purpose: merging them would make the surface
/// non-manifold). `widest`: the largest of their distances to their nearest such end. 0 (and
/// `reach` 0) when the median side is 1e-9 of the boundary's extent or less.
int NearBoundaryVertices(const std::vector<Vec3>& V, const std::vector<Tri>& F, const std::vector<int>& boundarySides,
                         double share, double& reach, double& widest);

/// Splits, for every boundary side in `boundarySides`, the face at every vertex of another
/// boundary side that lies within `tol` of the edge and more than `tol` from both its ends. A face with such vertices on
/// several of its sides is triangulated with all of them (no triangle of three collinear
/// vertices). The new faces keep the face's orientation; the other faces keep their order, the
/// split ones' pieces are appended. Returns how many vertices were inserted into edges (0: `F`
/// unchanged). Cost O(boundary length / mean boundary edge) grid look-ups.
int CloseTJunctions(const std::vector<Vec3>& V, std::vector<Tri>& F, const std::vector<int>& boundarySides, double tol);

}  // namespace vcgext
