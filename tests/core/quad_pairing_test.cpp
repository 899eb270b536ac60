// PairFauxHalves (vcg_ext/core/quad_pairing.h): the quads of a MeshLab pure-quad layer from its
// faux-edge triangle halves, including diagonals that several quads share.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "test_support.h"
#include "vcg_ext/core/quad_pairing.h"

namespace {

using vcgext::FauxHalves;
using vcgext::Quad;
using vcgext::QuadData;
using vcgext::Vec3;

// Each quad {a, d, b, c} split along a–b, as MeshLab stores it: (a, b, c) and (b, a, d), each with
// its faux edge in slot 0.
FauxHalves Split(const std::vector<Quad>& quads) {
  FauxHalves h;
  for (const Quad& q : quads) {
    h.tris.push_back({q[0], q[2], q[3]});
    h.tris.push_back({q[2], q[0], q[1]});
    h.fauxSlot.push_back(0);
    h.fauxSlot.push_back(0);
  }
  return h;
}

std::set<Quad> Canon(const std::vector<Quad>& quads) { return testsupport::CanonicalFaceSet(quads); }

}  // namespace

TEST(QuadPairing, OneToOneDiagonalsGiveTheQuadsBack) {
  QuadData out;
  out.V = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(2, 1, 0)};
  const std::vector<Quad> quads = {{0, 1, 4, 3}, {1, 2, 5, 4}};
  int ambiguous = -1;
  ASSERT_EQ(vcgext::PairFauxHalves(Split(quads), out, &ambiguous), "");
  EXPECT_EQ(ambiguous, 0);
  EXPECT_EQ(Canon(out.F), Canon(quads));
  for (const Quad& q : out.F)  // orientation kept: the same cyclic order, not reversed
    EXPECT_TRUE(Canon({q}) == Canon({quads[0]}) || Canon({q}) == Canon({quads[1]}));
}

TEST(QuadPairing, AHalfWithoutPartnerIsAnError) {
  QuadData out;
  out.V = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  FauxHalves h = Split({{0, 1, 2, 3}});
  h.tris.pop_back();
  h.fauxSlot.pop_back();
  const std::string err = vcgext::PairFauxHalves(h, out, nullptr);
  EXPECT_NE(err.find("1 faux edges have no consistently oriented partner"), std::string::npos) << err;
  // a partner with the same direction (both halves oriented alike) is no partner either
  h = Split({{0, 1, 2, 3}});
  std::swap(h.tris[1][0], h.tris[1][1]);  // (a, b, d): faux edge a→b, as the first half's
  EXPECT_NE(vcgext::PairFauxHalves(h, out, nullptr).find("2 faux edges"), std::string::npos);
}

// Two quads with the same opposite corners 0 and 2 (Q1 = 0 1 2 3, Q2 = 0 4 2 5) inside a closed
// ring of quads round both corners (A, B round 0; C, D round 2): the diagonal 0–2 carries two
// halves in each direction. The coordinates make the normals mislead (Q1's and Q2's true halves
// disagree, the crossed ones agree, as in a folded region), so the greedy pairing by normals
// crosses them; the crossed pairing splits the quad fans at 0 and 2 in two, and the untangling
// step restores the true quads.
TEST(QuadPairing, SharedDiagonalMisledByNormalsIsUntangledByTheFans) {
  QuadData out;
  out.V = {Vec3(0, 0, 0),    Vec3(1, 1, 0.5), Vec3(2, 0, 0),   Vec3(1, 1, 0),  Vec3(1, -1, 0),
           Vec3(1, -1, 0.5), Vec3(0, 2, 1),   Vec3(0, -2, 1),  Vec3(2, 2, 1),  Vec3(2, -2, 1)};
  const std::vector<Quad> q12 = {{0, 1, 2, 3}, {0, 4, 2, 5}};
  const std::vector<Quad> ring = {{0, 5, 6, 1}, {0, 3, 7, 4}, {2, 4, 8, 3}, {2, 1, 9, 5}};
  // the premise: the greedy pairing alone would cross Q1 and Q2
  QuadData alone = out;
  int ambiguous = -1;
  ASSERT_EQ(vcgext::PairFauxHalves(Split(q12), alone, &ambiguous), "");
  EXPECT_EQ(ambiguous, 1);
  EXPECT_NE(Canon(alone.F), Canon(q12)) << "the normals do not mislead: the test proves nothing";
  std::vector<Quad> all = q12;
  all.insert(all.end(), ring.begin(), ring.end());
  ambiguous = -1;
  ASSERT_EQ(vcgext::PairFauxHalves(Split(all), out, &ambiguous), "");
  EXPECT_EQ(ambiguous, 1);
  EXPECT_EQ(Canon(out.F), Canon(all));
}

namespace {

// Polygon `loop` fanned from its first corner, as vcglib's PLY importer stores it: triangle i is
// (c0, c(i+1), c(i+2)), its edge 0 faux unless i = 0, its edge 2 faux unless it is the last.
void Fan(const std::vector<int>& loop, vcgext::FauxTriangles& t) {
  const int n = int(loop.size());
  for (int i = 0; i + 2 < n; ++i) {
    t.tris.push_back({loop[0], loop[i + 1], loop[i + 2]});
    t.faux.push_back({i > 0, false, i + 3 < n});
  }
}

std::set<std::vector<int>> CanonLoops(const std::vector<std::vector<int>>& loops) {
  return testsupport::CanonicalFaceSet(loops);
}

}  // namespace

TEST(PolygonsFromFauxTriangles, FansOfEverySizeGiveTheirPolygonsBack) {
  // A hexagon, a pentagon, a quad and a triangle sharing edges (a strip), each fanned.
  const std::vector<std::vector<int>> polys = {{0, 1, 2, 3, 4, 5}, {1, 0, 6, 7, 8}, {2, 1, 8, 9}, {3, 2, 9}};
  vcgext::FauxTriangles t;
  for (const auto& p : polys) Fan(p, t);
  ASSERT_EQ(t.tris.size(), 4u + 3u + 2u + 1u);
  std::vector<std::vector<int>> back;
  ASSERT_EQ(vcgext::PolygonsFromFauxTriangles(t, back), "");
  ASSERT_EQ(back.size(), polys.size());
  EXPECT_EQ(CanonLoops(back), CanonLoops(polys));
  for (size_t i = 0; i < polys.size(); ++i) EXPECT_EQ(back[i].size(), polys[i].size());  // in layer order
  // Another triangulation of the hexagon (a zig-zag, not a fan) gives the same polygon.
  vcgext::FauxTriangles z;
  z.tris = {{0, 1, 5}, {1, 2, 5}, {2, 4, 5}, {2, 3, 4}};
  z.faux = {{false, true, false}, {false, true, true}, {true, false, true}, {false, false, true}};
  back.clear();
  ASSERT_EQ(vcgext::PolygonsFromFauxTriangles(z, back), "");
  EXPECT_EQ(CanonLoops(back), CanonLoops({polys[0]}));
}

TEST(PolygonsFromFauxTriangles, FauxEdgesThatMakeNoPolygonAreErrors) {
  std::vector<std::vector<int>> out;
  // A faux edge without a partner.
  vcgext::FauxTriangles a;
  a.tris = {{0, 1, 2}};
  a.faux = {{true, false, false}};
  EXPECT_NE(vcgext::PolygonsFromFauxTriangles(a, out).find("no consistently oriented partner"), std::string::npos);
  // A quad fanned round an inner vertex 4, every spoke faux: a loop of 4 edges for 4 triangles.
  vcgext::FauxTriangles b;
  for (int k = 0; k < 4; ++k) {
    b.tris.push_back({k, (k + 1) % 4, 4});
    b.faux.push_back({false, true, true});
  }
  EXPECT_NE(vcgext::PolygonsFromFauxTriangles(b, out).find("inner vertex"), std::string::npos);
  // Three triangles on one faux edge, two running it the same way.
  vcgext::FauxTriangles c;
  c.tris = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  c.faux = {{true, false, false}, {true, false, false}, {true, false, false}};
  const std::string nonManifold = vcgext::PolygonsFromFauxTriangles(c, out);
  EXPECT_NE(nonManifold.find("run the same way by two triangles: 3 triangles have a faux edge shared by more than two"),
            std::string::npos)
      << nonManifold;
  EXPECT_NE(nonManifold.find("Repair non Manifold Edges"), std::string::npos) << nonManifold;
  EXPECT_EQ(nonManifold.find("Re-Orient"), std::string::npos) << "orienting cannot help it: " << nonManifold;
  // Two triangles running their faux edge the same way (half a quad stored reversed): orientation.
  vcgext::FauxTriangles d;
  d.tris = {{0, 1, 2}, {0, 1, 3}};
  d.faux = {{true, false, false}, {true, false, false}};
  const std::string reversed = vcgext::PolygonsFromFauxTriangles(d, out);
  EXPECT_NE(reversed.find("1 faux edges are run the same way by two triangles (faces of inconsistent orientation"),
            std::string::npos)
      << reversed;
  EXPECT_NE(reversed.find("Re-Orient all faces coherently"), std::string::npos) << reversed;
}

// OrientFauxTriangles: polygons stored reversed against their neighbours are flipped back, the
// majority's orientation kept, and the faux flags follow the edges, so the polygons read back as
// they were meant; a triangle reversed inside its quad too; a Moebius strip is reported.
TEST(OrientFauxTriangles, FlipsTheMinorityAndCarriesTheFauxFlags) {
  const std::vector<std::vector<int>> polys = {{0, 1, 2, 3, 4, 5}, {1, 0, 6, 7, 8}, {2, 1, 8, 9}, {3, 2, 9}};
  auto reversed = [](std::vector<int> p) { return std::vector<int>(p.rbegin(), p.rend()); };
  vcgext::FauxTriangles t;
  Fan(polys[0], t);            // 4 triangles
  Fan(reversed(polys[1]), t);  // 3, reversed
  Fan(polys[2], t);            // 2
  Fan(reversed(polys[3]), t);  // 1, reversed
  int nonOrientable = -1;
  EXPECT_EQ(vcgext::OrientFauxTriangles(t, &nonOrientable), 3 + 1);
  EXPECT_EQ(nonOrientable, 0);
  std::vector<std::vector<int>> back;
  ASSERT_EQ(vcgext::PolygonsFromFauxTriangles(t, back), "");
  EXPECT_EQ(CanonLoops(back), CanonLoops(polys));
  EXPECT_EQ(vcgext::OrientFauxTriangles(t), 0) << "coherent now";

  // One half of a quad reversed: its faux diagonal is run the same way twice until oriented.
  vcgext::FauxTriangles q;
  Fan({0, 1, 2, 3}, q);
  Fan({3, 2, 4, 5}, q);
  std::swap(q.tris[3][1], q.tris[3][2]);
  std::swap(q.faux[3][0], q.faux[3][2]);
  back.clear();
  EXPECT_NE(vcgext::PolygonsFromFauxTriangles(q, back).find("run the same way"), std::string::npos);
  EXPECT_EQ(vcgext::OrientFauxTriangles(q), 1);
  back.clear();
  ASSERT_EQ(vcgext::PolygonsFromFauxTriangles(q, back), "");
  EXPECT_EQ(CanonLoops(back), CanonLoops({{0, 1, 2, 3}, {3, 2, 4, 5}}));

  // A Moebius strip of six quads: top i, bottom i + 6; the last quad joins the first twisted.
  vcgext::FauxTriangles m;
  for (int i = 0; i < 6; ++i) {
    const int t0 = i, b0 = i + 6, t1 = i < 5 ? i + 1 : 6, b1 = i < 5 ? i + 7 : 0;
    Fan({t0, b0, b1, t1}, m);
  }
  EXPECT_EQ(vcgext::OrientFauxTriangles(m, &nonOrientable), 0);
  EXPECT_EQ(nonOrientable, 1);
}
