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

}  // namespace vcgext
