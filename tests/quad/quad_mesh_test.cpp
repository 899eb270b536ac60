// Local operators of the editable quad mesh (Fitmaps §3.3) on hand-built configurations, and
// long random operator sequences with the full validity check after each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "quad_test_util.h"
#include "vcg_ext/quad/quad_mesh.h"

using vcgext::quad::OpResult;
using vcgext::quad::QuadMesh;

namespace {
QuadMesh Make(const vcgext::QuadData& q) { return QuadMesh(q.V, q.F); }
int GridId(int i, int j, int nx) { return j * (nx + 1) + i; }
}  // namespace

TEST(QuadMesh, BuildAndCheck) {
  QuadMesh g = Make(quadtest::QuadGrid(4, 4));
  EXPECT_EQ(g.Check(), "");
  EXPECT_EQ(g.NumFaces(), 16);
  EXPECT_EQ(g.NumVertices(), 25);
  auto inv = g.ComputeInvariants();
  EXPECT_EQ(inv.components, 1);
  EXPECT_EQ(inv.eulerPerComponent, std::vector<int>{1});
  EXPECT_EQ(inv.boundaryLoops, 1);
  EXPECT_TRUE(g.IsBoundary(0));
  EXPECT_FALSE(g.IsBoundary(GridId(2, 2, 4)));
  EXPECT_EQ(g.Valence(0), 2);                 // grid corner: one face
  EXPECT_EQ(g.Valence(GridId(2, 0, 4)), 3);   // boundary regular
  EXPECT_EQ(g.Valence(GridId(2, 2, 4)), 4);
  QuadMesh c = Make(quadtest::CubeSphere(2));
  EXPECT_EQ(c.Check(), "");
  auto ic = c.ComputeInvariants();
  EXPECT_EQ(ic.eulerPerComponent, std::vector<int>{2});
  EXPECT_EQ(ic.boundaryLoops, 0);
  int irr = 0;
  auto h = c.ValenceHistogram(&irr);
  EXPECT_EQ(irr, 8);
  EXPECT_EQ(h[3], 8);
}

TEST(QuadMesh, CheckDetectsBrokenMeshes) {
  auto q = quadtest::QuadGrid(2, 2);
  q.F[0] = {q.F[0][0], q.F[0][3], q.F[0][2], q.F[0][1]};  // flipped orientation
  EXPECT_NE(Make(q).Check(), "");
  auto r = quadtest::QuadGrid(2, 2);
  r.F.push_back(r.F[3]);  // duplicated face: non-manifold edges
  EXPECT_NE(Make(r).Check(), "");
}

TEST(QuadMesh, CollapseInteriorValences) {
  QuadMesh g = Make(quadtest::QuadGrid(4, 4));
  auto inv = g.ComputeInvariants();
  const int f = 5;  // cell (1,1)
  const int a = GridId(1, 1, 4), b = GridId(2, 1, 4), c = GridId(2, 2, 4), d = GridId(1, 2, 4);
  ASSERT_EQ(g.F[f][0], a);
  vcgext::Vec3 mid = 0.5 * (g.P[a] + g.P[c]);
  int s = -1;
  ASSERT_EQ(g.CollapseDiagonal(f, 0, &s), OpResult::Ok);
  EXPECT_EQ(s, a);
  EXPECT_FALSE(g.VertAlive(c));
  EXPECT_FALSE(g.FaceAlive(f));
  EXPECT_EQ(g.Valence(a), 6);
  EXPECT_EQ(g.Valence(b), 3);
  EXPECT_EQ(g.Valence(d), 3);
  EXPECT_NEAR((g.P[a] - mid).norm(), 0.0, 1e-15);
  EXPECT_EQ(g.NumFaces(), 15);
  EXPECT_EQ(g.Check(&inv), "");
}

TEST(QuadMesh, CollapseBoundaryKeepsBoundaryVertex) {
  QuadMesh g = Make(quadtest::QuadGrid(4, 4));
  auto inv = g.ComputeInvariants();
  // face 0 = (0, 1, 6, 5): diagonal 1-5 joins two boundary vertices
  EXPECT_EQ(g.CollapseDiagonal(0, 1), OpResult::BoundaryMerge);
  EXPECT_EQ(g.Check(&inv), "");
  int s = -1;
  ASSERT_EQ(g.CollapseDiagonal(0, 0, &s), OpResult::Ok);
  EXPECT_EQ(s, 0);
  EXPECT_TRUE(g.IsBoundary(s));
  EXPECT_NEAR(g.P[0].norm(), 0.0, 1e-15);  // boundary survivor keeps its position
  EXPECT_EQ(g.Valence(1), 2);               // became a boundary corner (allowed)
  EXPECT_EQ(g.Check(&inv), "");
  // a boundary corner whose only face dies would become isolated: refused
  QuadMesh one = Make(quadtest::QuadGrid(1, 1));
  EXPECT_NE(one.CollapseDiagonal(0, 0), OpResult::Ok);
  EXPECT_EQ(one.Check(), "");
}

TEST(QuadMesh, DoubletCreatedAndRemoved) {
  QuadMesh g = Make(quadtest::QuadGrid(4, 4));
  auto inv = g.ComputeInvariants();
  const int b = GridId(2, 1, 4);
  ASSERT_EQ(g.CollapseDiagonal(5, 0), OpResult::Ok);
  ASSERT_EQ(g.Valence(b), 3);
  // collapse a face at b along the diagonal that does not contain b: b gets valence 2
  int target = -1, kk = -1;
  for (int f : g.VF(b)) {
    int k = g.CornerOf(f, b);
    if (!g.IsBoundary(g.F[f][(k + 1) & 3]) || !g.IsBoundary(g.F[f][(k + 3) & 3])) {
      target = f;
      kk = (k + 1) & 1;
      break;
    }
  }
  ASSERT_GE(target, 0);
  ASSERT_EQ(g.CollapseDiagonal(target, kk), OpResult::Ok);
  EXPECT_EQ(g.Valence(b), 2);
  EXPECT_NE(g.Check(&inv).find("valence 2"), std::string::npos);
  EXPECT_EQ(g.RemoveDoublet(GridId(0, 0, 4)), OpResult::NotDoublet);
  ASSERT_EQ(g.RemoveDoublet(b), OpResult::Ok);
  EXPECT_FALSE(g.VertAlive(b));
  EXPECT_EQ(g.Check(&inv), "");
}

TEST(QuadMesh, BoundaryCornerRemoval) {
  // collapse a boundary face towards its boundary corner: the next boundary vertex becomes a
  // one-face vertex on a straight boundary, which RemoveBoundaryCorner removes.
  QuadMesh g = Make(quadtest::QuadGrid(4, 4));
  auto inv = g.ComputeInvariants();
  const int f = 1;  // cell (1,0): corners 1, 2, 7, 6
  ASSERT_EQ(g.CollapseDiagonal(f, 1), OpResult::Ok);  // diagonal 2-6: 2 boundary survives
  const int b = 1;  // (1,0): lost its face towards cell (1,0)
  ASSERT_EQ(g.VF(b).size(), 1u);
  EXPECT_EQ(g.Valence(b), 2);
  EXPECT_EQ(g.Check(&inv), "");
  const int nb = g.NumVertices(), nf = g.NumFaces();
  EXPECT_EQ(g.RemoveBoundaryCorner(GridId(2, 2, 4)), OpResult::NotDoublet);  // interior
  int s = -1;
  ASSERT_EQ(g.RemoveBoundaryCorner(b, &s, 1), OpResult::Ok);
  EXPECT_EQ(g.NumVertices(), nb - 2);
  EXPECT_EQ(g.NumFaces(), nf - 1);
  EXPECT_EQ(s, 0);                          // keep = 1: survivor a = the grid corner (0,0)
  EXPECT_NEAR(g.P[0].norm(), 0.0, 1e-15);  // at its position
  EXPECT_EQ(g.Check(&inv), "");
  // on a single quad the removal would leave nothing valid: refused, mesh unchanged
  QuadMesh one = Make(quadtest::QuadGrid(1, 1));
  EXPECT_NE(one.RemoveBoundaryCorner(0), OpResult::Ok);
  EXPECT_EQ(one.Check(), "");
  EXPECT_EQ(one.NumFaces(), 1);
}

TEST(QuadMesh, SwapEnergyAndApply) {
  QuadMesh g = Make(quadtest::QuadGrid(4, 4));
  auto inv = g.ComputeInvariants();
  // interior edge of face 5 from corner 1 (2,1)->(2,2): shared with face 6
  const int f = 5, k = 1;
  int delta = 0;
  ASSERT_TRUE(g.SwapEnergyDelta(f, k, 0, &delta));
  EXPECT_EQ(delta, 4);  // all six vertices regular interior: two lose, two gain a valence
  EXPECT_FALSE(g.SwapEnergyDelta(0, 0, 0, &delta));  // boundary edge
  EXPECT_EQ(g.SwapEdge(0, 0, 0), OpResult::BoundaryEdge);
  const int u = g.F[f][1], v = g.F[f][2];
  ASSERT_EQ(g.SwapEdge(f, k, 0), OpResult::Ok);
  EXPECT_EQ(g.Valence(u), 3);
  EXPECT_EQ(g.Valence(v), 3);
  EXPECT_EQ(g.Check(&inv), "");
  // a swap that would leave a valence-2 interior vertex is refused: u now has valence 3
  bool refused = false;
  for (int h : std::vector<int>(g.VF(u))) {
    int c = g.CornerOf(h, u);
    if (g.AcrossEdge(h, c) < 0) continue;
    OpResult r = g.SwapEdge(h, c, 0);
    if (r == OpResult::LowValence) { refused = true; break; }
    if (r == OpResult::Ok) break;
  }
  EXPECT_TRUE(refused);
  EXPECT_EQ(g.Check(&inv), "");
}

TEST(QuadMesh, SwapImprovesValenceAroundValence5And3) {
  // a swap in a regular grid creates two valence-3 and two valence-5 vertices (energy +4); among
  // the swaps of the two touched faces one must undo that (energy -4) and restore regularity.
  QuadMesh g = Make(quadtest::QuadGrid(6, 6));
  auto inv = g.ComputeInvariants();
  const int f = 2 * 6 + 2;
  int g2 = g.AcrossEdge(f, 1);
  ASSERT_EQ(g.SwapEdge(f, 1, 0), OpResult::Ok);
  int irr = 0;
  g.ValenceHistogram(&irr);
  EXPECT_EQ(irr, 4 + 4);  // the grid corners (valence 2 on the boundary) + the 4 new ones
  int best = 0, bf = -1, bk = -1, bv = -1;
  for (int h : {f, g2})
    for (int k = 0; k < 4; ++k)
      for (int var = 0; var < 2; ++var) {
        int d;
        if (g.SwapEnergyDelta(h, k, var, &d) && d < best) { best = d; bf = h; bk = k; bv = var; }
      }
  EXPECT_EQ(best, -4);
  ASSERT_EQ(g.SwapEdge(bf, bk, bv), OpResult::Ok);
  int irr2 = 0;
  g.ValenceHistogram(&irr2);
  EXPECT_EQ(irr2, irr - 4);
  EXPECT_EQ(g.Check(&inv), "");
}

TEST(QuadMesh, CubeCollapseCascadeIsRefusedAndRolledBack) {
  // On a cube every collapse leaves doublets; the cascade ends in a degenerate configuration,
  // which is refused, and Rollback restores the cube exactly.
  auto q = quadtest::CubeSphere(1);
  QuadMesh c = Make(q);
  auto inv = c.ComputeInvariants();
  c.Begin();
  ASSERT_EQ(c.CollapseDiagonal(0, 0), OpResult::Ok);
  int refusals = 0, removed = 0;
  for (int pass = 0; pass < 4; ++pass)
    for (int v = 0; v < c.NumVertexSlots(); ++v)
      if (c.VertAlive(v) && c.Valence(v) == 2) {
        OpResult r = c.RemoveDoublet(v);
        if (r == OpResult::Ok) ++removed; else ++refusals;
      }
  // 5 faces -> 3 doublet removals -> the 2-quad "pillow" (valence 2 everywhere); removing one
  // more doublet would make a face with a repeated vertex: refused.
  EXPECT_EQ(removed, 3);
  EXPECT_GT(refusals, 0);
  EXPECT_EQ(c.NumFaces(), 2);
  c.Rollback();
  EXPECT_EQ(c.Check(&inv), "");
  EXPECT_EQ(c.NumFaces(), 6);
  for (int f = 0; f < 6; ++f) EXPECT_EQ(c.F[f], q.F[f]);
  for (size_t v = 0; v < q.V.size(); ++v) EXPECT_EQ(c.P[v], q.V[v]);
}

namespace {
// Random collapse / swap / doublet sequence; validity checked after every committed step.
void RandomOps(QuadMesh m, unsigned seed, int steps, int minFaces, int* linkRefusals) {
  auto inv = m.ComputeInvariants();
  std::mt19937 rng(seed);
  int collapses = 0, swaps = 0, doublets = 0, refusedLink = 0;
  for (int it = 0; it < steps && m.NumFaces() > minFaces; ++it) {
    int op = int(rng() % 3);
    int f = int(rng() % m.NumFaceSlots());
    if (!m.FaceAlive(f)) continue;
    if (op == 0) {
      m.Begin();
      int k = int(rng() % 2);
      OpResult r = m.CollapseDiagonal(f, k);
      bool ok = r == OpResult::Ok;
      if (r == OpResult::NonManifold || r == OpResult::Degenerate) ++refusedLink;
      int removed = 0;
      for (int pass = 0; ok && pass < 6; ++pass)
        for (int v = 0; ok && v < m.NumVertexSlots(); ++v)
          if (m.VertAlive(v) && !m.IsBoundary(v) && m.Valence(v) == 2) {
            OpResult rd = m.RemoveDoublet(v);
            if (rd != OpResult::Ok) { ok = false; ++refusedLink; } else ++removed;
          }
      if (ok) { m.Commit(); ++collapses; doublets += removed; } else m.Rollback();
    } else if (op == 1) {
      OpResult r = m.SwapEdge(f, int(rng() % 4), int(rng() % 2));
      if (r == OpResult::Ok) ++swaps;
      if (r == OpResult::NonManifold || r == OpResult::Degenerate) ++refusedLink;
    } else {
      int v = m.F[f][rng() % 4];
      if (m.RemoveDoublet(v) == OpResult::Ok) ++doublets;
      if (m.VertAlive(v) && m.IsBoundary(v) && m.VF(v).size() == 1) {
        m.Begin();
        bool ok = m.RemoveBoundaryCorner(v, nullptr, int(rng() % 3)) == OpResult::Ok;
        for (int pass = 0; ok && pass < 6; ++pass)
          for (int x = 0; ok && x < m.NumVertexSlots(); ++x)
            if (m.VertAlive(x) && !m.IsBoundary(x) && m.Valence(x) == 2) ok = m.RemoveDoublet(x) == OpResult::Ok;
        if (ok) m.Commit(); else m.Rollback();
      }
    }
    std::string err = m.Check(&inv);
    ASSERT_EQ(err, "") << "after step " << it << " (op " << op << ")";
  }
  EXPECT_GT(collapses, 10);
  EXPECT_GT(swaps, 0);
  *linkRefusals += refusedLink;
  testing::Test::RecordProperty("doublets", doublets);
}
}  // namespace

TEST(QuadMesh, RandomSequencesClosed) {
  int refusals = 0;
  auto c = quadtest::CubeSphere(5);
  for (unsigned seed = 1; seed <= 8; ++seed) RandomOps(QuadMesh(c.V, c.F), seed, 4000, 6, &refusals);
  EXPECT_GT(refusals, 0) << "the link condition was never exercised";
}

TEST(QuadMesh, RandomSequencesOpen) {
  int refusals = 0;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    auto g = quadtest::QuadGrid(8, 6);
    RandomOps(QuadMesh(g.V, g.F), seed, 4000, 6, &refusals);
  }
  (void)refusals;  // open grids rarely hit the link condition (boundary merges are refused first)
}

TEST(QuadMesh, RandomSequencesTorus) {
  // torus: 8 x 6 grid with both directions wrapped (genus 1, Euler characteristic 0)
  const int nu = 8, nv = 6;
  vcgext::QuadData q;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      double a = 2 * M_PI * i / nu, b = 2 * M_PI * j / nv;
      q.V.emplace_back((2 + std::cos(b)) * std::cos(a), (2 + std::cos(b)) * std::sin(a), std::sin(b));
    }
  auto id = [&](int i, int j) { return (j % nv) * nu + (i % nu); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) q.F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  QuadMesh t(q.V, q.F);
  ASSERT_EQ(t.Check(), "");
  EXPECT_EQ(t.ComputeInvariants().eulerPerComponent, std::vector<int>{0});
  int refusals = 0;
  for (unsigned seed = 1; seed <= 4; ++seed) RandomOps(t, seed, 3000, 4, &refusals);
  EXPECT_GT(refusals, 0) << "the link condition was never exercised";
}

// A fan of m quads around vertex 0 (a closed disk, or with `open` one quad left out: a half-disk),
// the faces in shuffled order: Fan orders them in a walk, w[i+1].p == w[i].n, every face once,
// for valences on both sides of the pairwise / sorted switch (16); a second fan glued at the
// vertex makes it non-manifold (false).
TEST(QuadMesh, FanOrdersEveryValenceAndRefusesTwoFans) {
  std::mt19937 rng(4);
  for (int m : {3, 5, 16, 17, 40, 300})
    for (bool open : {false, true})
      for (bool twoFans : {false, true}) {
        SCOPED_TRACE("valence " + std::to_string(m) + (open ? " open" : " closed") + (twoFans ? " two fans" : ""));
        std::vector<vcgext::Vec3> V = {vcgext::Vec3(0, 0, 0)};
        for (int i = 0; i < 2 * m; ++i) {
          const double a = M_PI * i / m;  // rim vertices 1 .. 2m: spokes (odd i) and between them
          V.push_back(vcgext::Vec3(std::cos(a), std::sin(a), 0) * (i % 2 ? 1.5 : 1.0));
        }
        std::vector<vcgext::Quad> F;
        auto rim = [&](int i) { return 1 + (i % (2 * m)); };
        for (int i = 0; i < m - (open ? 1 : 0); ++i) F.push_back({0, rim(2 * i), rim(2 * i + 1), rim(2 * i + 2)});
        if (twoFans) {  // a second disk of 3 quads touching vertex 0 only
          const int b = int(V.size());
          for (int i = 0; i < 6; ++i) V.push_back(vcgext::Vec3(std::cos(i), std::sin(i), 5));
          for (int i = 0; i < 3; ++i) F.push_back({0, b + 2 * i, b + 2 * i + 1, b + (2 * i + 2) % 6});
        }
        std::shuffle(F.begin(), F.end(), rng);
        const QuadMesh K(V, F);
        std::vector<vcgext::quad::Wedge> w;
        bool isOpen = !open;
        const bool ok = K.Fan(0, w, &isOpen);
        if (twoFans) {
          EXPECT_FALSE(ok);
          continue;
        }
        ASSERT_TRUE(ok);
        EXPECT_EQ(isOpen, open);
        ASSERT_EQ(int(w.size()), m - (open ? 1 : 0));
        std::set<int> faces;
        for (size_t i = 0; i < w.size(); ++i) {
          faces.insert(w[i].f);
          EXPECT_EQ(F[size_t(w[i].f)][size_t(w[i].k)], 0);
          if (i + 1 < w.size()) {
            EXPECT_EQ(w[i + 1].p, w[i].n);
          }
        }
        EXPECT_EQ(faces.size(), w.size());
        if (open) {
          EXPECT_EQ(w.front().p, rim(2 * (m - 1)));  // the rim vertex after the gap
          // an open fan starts at the wedge whose p is no wedge's n
          for (const auto& x : w) EXPECT_NE(x.n, w.front().p);
        } else {
          EXPECT_EQ(w.front().p, w.back().n);  // closed: the walk comes round
        }
      }
}
