#pragma once
/// \file tri_to_quad.h
/// Triangle mesh -> pure-quad mesh on the same vertices (Fitmaps §3.2, after Tarini et al.,
/// "Practical quad mesh simplification", 2010): triangles are paired across shared edges.
///  1. greedy pairing by quad quality (best first: corner angles near 90 degrees, planar);
///  2. augmenting alternating paths to pair the leftovers: a plain breadth-first search, then
///     Edmonds' blossom search for what it misses (the dual of a closed triangle mesh is a
///     bridgeless cubic graph, which has a perfect matching by Petersen's theorem, but it has odd
///     cycles, around which the plain search can miss the path: bunny00 x4 left 2 triangles);
///  3. triangles still unpaired (odd counts, only possible with boundaries; blocked pairings)
///     move along an alternating path to a triangle with a boundary edge, which is split at the
///     edge midpoint into two paired halves (one new boundary vertex of valence 2 per split);
///     interior vertices left in only two quads (doublets) are then merged away (the vertex
///     stays in V, unreferenced);
///  4. validation against the triangle mesh's topology (QuadMesh::Check with the Euler
///     characteristic and boundary loops per component); vertices where the result is invalid
///     (an interior doublet that cannot be merged, two quads sharing two edges) are repaired by
///     pairing again with every edge at them forbidden, up to `maxRepairRounds` times;
///  5. fallback when pairing still fails: every input triangle split into 3 quads (edge
///     midpoints + centre): always a valid pure-quad mesh on a manifold, oriented input.
#include <string>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {
namespace quad {

enum class TriToQuadPath {
  AlreadyQuads,       ///< the caller's quads were used as they are
  Pairing,            ///< every triangle paired (greedy + augmenting paths), same vertices
  PairingBoundarySplit,  ///< as Pairing, with some boundary triangles split (odd count / leftovers)
  SplitAll,           ///< pairing failed: every triangle split into 3 quads (more vertices)
};
const char* ToString(TriToQuadPath p);

struct TriToQuadParams {
  bool allowSplitFallback = true;  ///< false: fail (error) instead of splitting everything
  /// passes of the plain augmenting-path search over the unmatched triangles; then one blossom
  /// search per triangle still unmatched (0 = neither: greedy pairing only, for tests)
  int maxAugmentPasses = 8;
  int maxRepairRounds = 4;         ///< re-pairings that forbid the edges at invalid vertices (step 4)
};

struct TriToQuadResult {
  std::string error;
  QuadData quads;            ///< V starts with the input vertices (new ones appended)
  TriToQuadPath path = TriToQuadPath::Pairing;
  int greedyPairs = 0;       ///< pairs made by the greedy pass
  int augmentedPairs = 0;    ///< pairs added by augmenting paths
  int unpairedTriangles = 0; ///< triangles left after pairing (0 unless SplitAll)
  int addedVertices = 0;
  int boundarySplits = 0;    ///< boundary triangles split into two paired halves
  int doubletsRemoved = 0;   ///< interior valence-2 vertices merged away after pairing
  int repairRounds = 0;      ///< re-pairings needed (step 4)
  int repairedVertices = 0;  ///< vertices whose edges were forbidden for pairing
};

/// Converts `m` into pure quads. Preconditions: m is manifold and consistently oriented (checked
/// by the caller; non-manifold edges are simply not paired across). Cost: O(F log F) + the
/// augmenting searches (bounded BFS per unmatched triangle).
TriToQuadResult TriToQuad(const TriData& m, const TriToQuadParams& p = {});

/// Splits every triangle into 3 quads and every quad into 4 (midpoints + centres). Used as the
/// fallback; exposed for tests.
QuadData SplitToQuads(const std::vector<Vec3>& V, const std::vector<Tri>& tris, const std::vector<Quad>& quads);

}  // namespace quad
}  // namespace vcgext
