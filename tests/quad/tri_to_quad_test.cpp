// Tri-to-quad (Fitmaps §3.2): pairing on the same vertices, odd counts, failing pairings.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/bitquad_creation.h>

#include "quad_test_util.h"
#include "vcg_ext/core/mesh_types.h"
#include "vcg_ext/core/vcg_bridge.h"
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
  // no boundary can absorb them, so the fallback splits every triangle into 3 quads.
  auto t = testsupport::Icosphere(2);
  vcgext::quad::TriToQuadParams p;
  p.maxAugmentPasses = 0;
  auto r = vcgext::quad::TriToQuad(t, p);
  ASSERT_GT(r.unpairedTriangles, 0) << "greedy alone paired everything: pick another mesh";
  ExpectValidQuads(t, r);
  EXPECT_EQ(r.path, TriToQuadPath::SplitAll);
  EXPECT_EQ(r.quads.F.size(), 3 * t.F.size());
  EXPECT_EQ(r.quads.V.size(), t.V.size() + t.F.size() + t.F.size() * 3 / 2);  // + centres + midpoints
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

// vcglib's BitQuadCreation (what MeshLab's "Tri to Quad by smart triangle pairing" builds on) as
// the reference the issue names: MakeDominant(2) + MakePureByFlip. On real scans it also reaches
// pure quads, but by flipping edges (quads that are not unions of two input triangles) and it
// leaves doublets; ours pairs input triangles only, leaves none, with quad shapes as good.
// Measured (quads; valence != 4; mean |corner angle - 90|; doublets):
//   bunny00   ours 37537, 16904, 26.5 deg, 0   vcglib 37393*, 17111, 26.2 deg, 311
//   elephant  ours  2772,  1314, 25.7 deg, 0   vcglib  2761*,  1348, 25.1 deg,  18
//   (* after merging the doublets). Decision in docs/quad.md.
TEST(TriToQuad, ComparedWithVcglibBitQuadCreation) {
  for (const char* name : {"elephant.off", "fandisk.off"}) {
    auto t = testsupport::LoadSample(name);
    auto ours = vcgext::quad::TriToQuad(t);
    ExpectValidQuads(t, ours);
    vcgext::TMesh m;
    testsupport::ToVcg(t, m);
    vcg::tri::UpdateTopology<vcgext::TMesh>::FaceFace(m);
    vcg::tri::UpdateFlags<vcgext::TMesh>::FaceBorderFromFF(m);
    vcg::tri::BitQuadCreation<vcgext::TMesh>::MakeTriEvenBySplit(m);
    vcg::tri::BitQuadCreation<vcgext::TMesh>::MakeDominant(m, 2);
    const bool pure = vcg::tri::BitQuadCreation<vcgext::TMesh>::MakePureByFlip(m);
    vcgext::QuadData theirs;
    ASSERT_EQ(vcgext::ImportQuads(m, theirs), "") << name;
    EXPECT_TRUE(pure) << name;
    // Ours: every quad is two input triangles sharing an edge; vcglib's flips make other quads.
    std::set<std::pair<int, int>> inputEdges;
    for (const auto& f : t.F)
      for (int k = 0; k < 3; ++k) inputEdges.insert(std::minmax(f[k], f[(k + 1) % 3]));
    auto quadsOffInputEdges = [&](const vcgext::QuadData& q) {
      int off = 0;
      for (const auto& f : q.F)
        for (int k = 0; k < 4; ++k)
          if (!inputEdges.count(std::minmax(f[k], f[(k + 1) % 4]))) { ++off; break; }
      return off;
    };
    EXPECT_EQ(quadsOffInputEdges(ours.quads), 0) << name;
    EXPECT_GT(quadsOffInputEdges(theirs), 0) << name;
    // Doublets (interior valence 2): none in ours, some in vcglib's.
    auto doublets = [](const vcgext::QuadData& q) {
      vcgext::quad::QuadMesh qm(q.V, q.F);
      int n = 0;
      for (int v = 0; v < qm.NumVertexSlots(); ++v)
        if (qm.VertAlive(v) && !qm.IsBoundary(v) && qm.Valence(v) == 2) ++n;
      return n;
    };
    EXPECT_EQ(doublets(ours.quads), 0) << name;
    EXPECT_GT(doublets(theirs), 0) << name;
  }
}
