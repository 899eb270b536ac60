// Tri-to-quad (Fitmaps §3.2): pairing on the same vertices, odd counts, failing pairings.
#include <gtest/gtest.h>

#include <set>

#include "quad_test_util.h"
#include "test_support.h"
#include "vcg_ext/quad/quad_mesh.h"
#include "vcg_ext/quad/tri_to_quad.h"

using vcgext::quad::TriToQuadPath;

namespace {
// Pure quads, valid, same invariants as the triangle mesh (Euler characteristic, boundary loops).
void ExpectValidQuads(const vcgext::TriData& t, const vcgext::quad::TriToQuadResult& r) {
  ASSERT_EQ(r.error, "");
  vcgext::quad::QuadMesh q(r.quads.V, r.quads.F);
  EXPECT_EQ(q.Check(), "");
  // Euler characteristic of the triangle mesh: V - E + F
  std::set<std::pair<int, int>> edges;
  for (auto& f : t.F)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(f[k], f[(k + 1) % 3]));
  int chi = int(t.V.size()) - int(edges.size()) + int(t.F.size());
  auto inv = q.ComputeInvariants();
  ASSERT_EQ(inv.components, 1);
  EXPECT_EQ(inv.eulerPerComponent[0], chi);
  // input vertices kept at their positions
  for (size_t i = 0; i < t.V.size(); ++i) EXPECT_EQ(r.quads.V[i], t.V[i]);
}
}  // namespace

TEST(TriToQuad, ClosedSpherePairsEverything) {
  auto t = testsupport::Icosphere(3);  // 1280 triangles
  auto r = vcgext::quad::TriToQuad(t);
  ExpectValidQuads(t, r);
  EXPECT_EQ(r.path, TriToQuadPath::Pairing);
  EXPECT_EQ(int(r.quads.F.size()), 640);
  EXPECT_EQ(r.quads.V.size(), t.V.size());
  EXPECT_EQ(r.unpairedTriangles, 0);
  EXPECT_EQ(r.greedyPairs + r.augmentedPairs, 640);
}

TEST(TriToQuad, TriangulatedQuadGridRecoversTheGrid) {
  // greedy by quality must pick the original diagonals' partners: right-angle quads
  auto t = quadtest::Triangulate(quadtest::QuadGrid(6, 5));
  auto r = vcgext::quad::TriToQuad(t);
  ExpectValidQuads(t, r);
  EXPECT_EQ(r.path, TriToQuadPath::Pairing);
  EXPECT_EQ(r.quads.F.size(), 30u);
  vcgext::quad::QuadMesh q(r.quads.V, r.quads.F);
  int irr = 0;
  q.ValenceHistogram(&irr);
  EXPECT_EQ(irr, 4);  // only the 4 grid corners
}

TEST(TriToQuad, OddCountSplitsOneBoundaryTriangle) {
  auto t = testsupport::PlaneGrid(5, 5);
  t.F.pop_back();  // 49 triangles
  auto r = vcgext::quad::TriToQuad(t);
  ExpectValidQuads(t, r);
  EXPECT_EQ(r.path, TriToQuadPath::PairingBoundarySplit);
  EXPECT_EQ(r.addedVertices, r.boundarySplits);
  EXPECT_GE(r.boundarySplits, 1);
  EXPECT_EQ(int(r.quads.F.size()), (49 - r.boundarySplits) / 2 + r.boundarySplits - r.doubletsRemoved);
}

TEST(TriToQuad, BlockedPairingOnOpenMeshUsesBoundarySplits) {
  // triangles A-B-C in a row and D attached to B only: B can pair with one of its three
  // neighbours, two triangles stay unpaired; both reach the boundary and are split there.
  vcgext::TriData t;
  t.V = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {-0.5, 1, 0}, {1.5, 1, 0}, {0.5, -1, 0}};
  t.F = {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}, {0, 5, 1}};
  auto r = vcgext::quad::TriToQuad(t);
  ExpectValidQuads(t, r);
  EXPECT_EQ(r.path, TriToQuadPath::PairingBoundarySplit);
  EXPECT_EQ(r.boundarySplits, 2);
  EXPECT_EQ(r.quads.F.size(), 3u);
}

TEST(TriToQuad, FailedPairingFallsBackToSplitting) {
  // closed mesh, augmenting paths disabled: the greedy pass alone leaves triangles unpaired and
  // no boundary can absorb them, so the fallback splits every face (always pure quads).
  auto t = testsupport::Icosphere(2);
  vcgext::quad::TriToQuadParams p;
  p.maxAugmentPasses = 0;
  auto r = vcgext::quad::TriToQuad(t, p);
  ASSERT_GT(r.unpairedTriangles, 0) << "greedy alone paired everything: pick another mesh";
  ExpectValidQuads(t, r);
  EXPECT_EQ(r.path, TriToQuadPath::SplitAll);
  // split: each pair -> 4 quads, each lone triangle -> 3 quads
  EXPECT_EQ(int(r.quads.F.size()), 4 * r.greedyPairs + 3 * r.unpairedTriangles);
  p.allowSplitFallback = false;
  auto r2 = vcgext::quad::TriToQuad(t, p);
  EXPECT_NE(r2.error, "");
  // with augmenting paths the same mesh pairs completely
  auto r3 = vcgext::quad::TriToQuad(t);
  EXPECT_EQ(r3.path, TriToQuadPath::Pairing);
  EXPECT_GT(r3.augmentedPairs, 0);
}

TEST(TriToQuad, OddClosedPieceAndSingleTriangle) {
  vcgext::TriData one;
  one.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.F = {{0, 1, 2}};
  auto r = vcgext::quad::TriToQuad(one);
  ExpectValidQuads(one, r);
  EXPECT_EQ(r.quads.F.size(), 1u);  // split at a boundary midpoint, then paired
}

TEST(TriToQuad, RealScan) {
  auto t = testsupport::LoadSample("elephant.off");
  auto r = vcgext::quad::TriToQuad(t);
  ExpectValidQuads(t, r);
  EXPECT_NE(r.path, TriToQuadPath::SplitAll) << "unpaired: " << r.unpairedTriangles;
}
