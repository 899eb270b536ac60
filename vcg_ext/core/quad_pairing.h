#pragma once
/// \file quad_pairing.h
/// The mesh-type-free half of ImportQuads (vcg_bridge.h): pairing the triangles of a MeshLab
/// pure-quad layer across their faux edges.
#include <array>
#include <string>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Triangles with exactly one faux edge, in layer order: the halves of quads. Triangle i's faux
/// edge runs from tris[i][fauxSlot[i]] to tris[i][(fauxSlot[i] + 1) % 3].
struct FauxHalves {
  std::vector<std::array<int, 3>> tris;
  std::vector<int> fauxSlot;
};

/// Appends to out.F one quad per pair of halves sharing a faux diagonal in opposite directions
/// (out.V must hold the vertices the halves index). A diagonal shared by several pairs is
/// ambiguous: greedy matching by the agreement of the halves' normals, then, for diagonals shared
/// by exactly two quads, the pairing with fewer fans at the diagonal's ends; `ambiguousResolved`
/// (optional) is set to the number of such diagonals. Returns "" or how many halves found no partner.
std::string PairFauxHalves(const FauxHalves& h, QuadData& out, int* ambiguousResolved);

/// The triangles of a MeshLab polygonal layer, each with its faux-edge flags: a polygon is the
/// triangles joined across faux edges (a quad two, an n-gon n - 2), a triangle has none.
/// Triangle i's edge k runs from tris[i][k] to tris[i][(k + 1) % 3] and is faux when faux[i][k].
struct FauxTriangles {
  std::vector<std::array<int, 3>> tris;
  std::vector<std::array<bool, 3>> faux;
};

/// The polygons of `t` (counter-clockwise vertex loops, in the order of their first triangle;
/// each loop starts at the first corner of that triangle that starts a non-faux edge) appended to
/// `polys`. Returns "" or what is wrong: a faux edge with no partner running it the opposite way, run
/// the same way by two triangles (inconsistent orientation) or shared by more than two, or a group whose non-faux edges are not one loop round all
/// its corners (a polygon with a hole or an inner vertex: n - 2 triangles for n sides).
std::string PolygonsFromFauxTriangles(const FauxTriangles& t, std::vector<std::vector<int>>& polys);

/// Orients the triangles of `t` coherently per connected component, across every edge of exactly
/// two triangles (faux or not), keeping the orientation of each component's majority
/// (OrientComponents, as the working copy of an input is oriented: input_prep.h); a flipped
/// triangle's faux flags follow its edges. A control layer some of whose polygons were stored
/// reversed (an export, a merge of parts) then reads as the author meant it. Returns the
/// triangles flipped; `nonOrientable` (optional) counts the components that cannot be oriented
/// (left as they are). A list with a degenerate triangle (a corner repeated) is left as it is.
int OrientFauxTriangles(FauxTriangles& t, int* nonOrientable = nullptr);

/// Cage q as the next filter reads it back from a MeshLab layer (ExportQuads, then ImportQuads
/// and ApplyInputCoordinatePrecision, as the fit filter reads its control layer): coordinates
/// rounded to the layer's scalar (float in MeshLab 2020.09; double in the 2025 build that PyMeshLab
/// loads, MESHLAB_SCALAR, which the reader then rounds to float unless that would move them, a
/// far-off cage), every quad split along its free diagonal
/// (FreeDiagonalStarts) and paired again, so a quad split along b-d starts at its corner b. The
/// fit depends on where a quad's corners start where it does not converge (a swept cage of
/// bunny00: 0.860 per mille as given, 0.908 read back), so whatever predicts the report fits this.
/// No faces when the pairing fails.
QuadData LayerRoundTrip(const QuadData& q);

}  // namespace vcgext
