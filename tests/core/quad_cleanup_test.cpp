// Doublet removal on foreign quad meshes (e.g. MeshLab's triangle pairing produces doublets).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "test_support.h"
#include "vcg_ext/core/quad_cleanup.h"

namespace {

// Unit cube as 6 quads (counter-clockwise seen from outside).
vcgext::QuadData Cube() {
  vcgext::QuadData q;
  for (int i = 0; i < 8; ++i) q.V.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  q.F = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return q;
}

// Splits quad f = (a,x,b,y) into the doublet (v,a,x,b), (v,b,y,a) with v at its centre.
void InsertDoublet(vcgext::QuadData& q, int f) {
  auto [a, x, b, y] = q.F[f];
  int v = int(q.V.size());
  q.V.push_back(0.25 * (q.V[a] + q.V[x] + q.V[b] + q.V[y]));
  q.F[f] = {v, a, x, b};
  q.F.push_back({v, b, y, a});
}

int EulerCharacteristic(const vcgext::QuadData& q) {
  std::set<std::pair<int, int>> e;
  std::set<int> v;
  for (const auto& f : q.F)
    for (int k = 0; k < 4; ++k) {
      e.insert(std::minmax(f[k], f[(k + 1) % 4]));
      v.insert(f[k]);
    }
  return int(v.size()) - int(e.size()) + int(q.F.size());
}

TEST(RemoveDoublets, RestoresTheMergedQuadsOnACube) {
  auto q = Cube();
  InsertDoublet(q, 0);
  InsertDoublet(q, 3);
  ASSERT_EQ(q.F.size(), 8u);
  EXPECT_EQ(vcgext::RemoveDoublets(q), 2);
  EXPECT_EQ(q.F.size(), 6u);
  EXPECT_EQ(q.V.size(), 8u);  // the two doublet centres are gone
  EXPECT_EQ(EulerCharacteristic(q), 2);
  // Every vertex has valence 3 again, and every directed edge appears once (orientation kept).
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : q.F)
    for (int k = 0; k < 4; ++k) ++directed[{f[k], f[(k + 1) % 4]}];
  for (const auto& d : directed) {
    EXPECT_EQ(d.second, 1);
    EXPECT_EQ(directed.count({d.first.second, d.first.first}), 1u);
  }
}

TEST(RemoveDoublets, LeavesCleanMeshesAndBoundaryCornersAlone) {
  auto q = Cube();
  auto before = q.F;
  EXPECT_EQ(vcgext::RemoveDoublets(q), 0);
  EXPECT_EQ(q.F, before);
  // A single open quad: its corners have valence 2 but are boundary vertices, not doublets.
  vcgext::QuadData s;
  s.V = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.F = {{0, 1, 2, 3}};
  EXPECT_EQ(vcgext::RemoveDoublets(s), 0);
  EXPECT_EQ(s.F.size(), 1u);
}

// A closed piece of two quads glued along all four edges (a pillow: what pairing a tetrahedron's
// triangles makes): its four corners are doublets no merge removes (the merged face would repeat
// every corner). CountDoublets counts them after RemoveDoublets; it counts removable ones before,
// and neither boundary corners nor a clean cube.
TEST(CountDoublets, CountsTheDoubletsRemoveDoubletsCannotMerge) {
  vcgext::QuadData pillow;
  pillow.V = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}};  // vertex 4 unused
  pillow.F = {{0, 1, 2, 3}, {3, 2, 1, 0}};
  EXPECT_EQ(vcgext::RemoveDoublets(pillow), 0);
  int first = -7;
  EXPECT_EQ(vcgext::CountDoublets(pillow, &first), 4);
  EXPECT_EQ(first, 0);
  // Beside a cube: the cube's vertices are not counted, the pillow's are (shifted by 8).
  auto q = Cube();
  for (const auto& f : pillow.F) q.F.push_back({f[0] + 8, f[1] + 8, f[2] + 8, f[3] + 8});
  for (int i = 0; i < 4; ++i) q.V.push_back(pillow.V[i]);
  EXPECT_EQ(vcgext::CountDoublets(q, &first), 4);
  EXPECT_EQ(first, 8);
  // Removable doublets are counted until removed.
  auto d = Cube();
  InsertDoublet(d, 2);
  EXPECT_EQ(vcgext::CountDoublets(d), 1);
  EXPECT_EQ(vcgext::RemoveDoublets(d), 1);
  EXPECT_EQ(vcgext::CountDoublets(d, &first), 0);
  EXPECT_EQ(first, -1);
  // An open quad's corners (valence 2, on the boundary) are no doublets; polygons alike.
  vcgext::PolyData open;
  open.V = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  open.F = {{0, 1, 2, 3}};
  EXPECT_EQ(vcgext::CountDoublets(open), 0);
  vcgext::PolyData two{open.V, {{0, 1, 2}, {2, 1, 0}}};  // two triangles glued: all three corners
  EXPECT_EQ(vcgext::CountDoublets(two), 3);
}

}  // namespace

namespace {
// Every quad on its own four vertices (an unwelded export).
vcgext::QuadData Unwelded(const vcgext::QuadData& q) {
  vcgext::QuadData u;
  for (const auto& f : q.F) {
    const int b = int(u.V.size());
    for (int k = 0; k < 4; ++k) u.V.push_back(q.V[f[k]]);
    u.F.push_back({b, b + 1, b + 2, b + 3});
  }
  return u;
}
}  // namespace

TEST(WeldCoincidentVertices, RestoresAnUnweldedCube) {
  auto q = Unwelded(Cube());
  ASSERT_EQ(q.V.size(), 24u);
  EXPECT_EQ(EulerCharacteristic(q), 6);  // six separate discs
  EXPECT_EQ(vcgext::WeldCoincidentVertices(q), 16);
  EXPECT_EQ(q.V.size(), 8u);
  ASSERT_EQ(q.F.size(), 6u);
  EXPECT_EQ(EulerCharacteristic(q), 2);
  // The same quads as the welded cube's, corner for corner, by coordinates.
  const auto cube = Cube();
  for (size_t f = 0; f < q.F.size(); ++f)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(q.V[q.F[f][k]], cube.V[cube.F[f][k]]) << f << " " << k;
  EXPECT_EQ(vcgext::WeldCoincidentVertices(q), 0);  // nothing left to weld
}

TEST(WeldCoincidentVertices, LeavesCleanMeshesAndPiecesApartOnPurposeAlone) {
  auto q = Cube();
  const auto before = q;
  EXPECT_EQ(vcgext::WeldCoincidentVertices(q), 0);
  EXPECT_EQ(q.F, before.F);
  // A square doubled with the same orientation: welding would make each edge run twice the same
  // way (two coincident sheets, not one surface): left apart.
  vcgext::QuadData d;
  for (int i = 0; i < 8; ++i) d.V.emplace_back(i & 1 ? 1 : 0, i & 2 ? 1 : 0, 0);
  d.F = {{0, 1, 3, 2}, {4, 5, 7, 6}};
  const auto d0 = d;
  EXPECT_EQ(vcgext::WeldCoincidentVertices(d), 0);
  EXPECT_EQ(d.F, d0.F);
  EXPECT_EQ(d.V.size(), d0.V.size());
  // Two closed cubes touching at a corner (the copies the filters' input preparation makes where
  // pieces touch): every edge would stay manifold, but the corner would get two fans: left apart.
  vcgext::QuadData two = Cube();
  const auto b = Cube();
  const int off = int(two.V.size());
  for (const auto& v : b.V) two.V.push_back(v + vcgext::Vec3(1, 1, 1));  // b's corner 0 on a's corner 7
  for (auto f : b.F) {
    for (int& c : f) c += off;
    two.F.push_back(f);
  }
  const auto two0 = two;
  EXPECT_EQ(vcgext::WeldCoincidentVertices(two), 0);
  EXPECT_EQ(two.F, two0.F);
  EXPECT_EQ(two.V.size(), 16u);
}

// The polygon version (before SubdivideOnce): a cube with one side as two triangles, every face
// on its own vertices, welds back to the 8 corners.
TEST(WeldCoincidentVertices, RestoresAnUnweldedPolygonalCube) {
  const auto cube = Cube();
  vcgext::PolyData p;
  auto add = [&](std::vector<int> corners) {
    std::vector<int> f;
    for (int c : corners) {
      f.push_back(int(p.V.size()));
      p.V.push_back(cube.V[c]);
    }
    p.F.push_back(f);
  };
  add({cube.F[0][0], cube.F[0][1], cube.F[0][2]});
  add({cube.F[0][0], cube.F[0][2], cube.F[0][3]});
  for (size_t f = 1; f < cube.F.size(); ++f) add({cube.F[f][0], cube.F[f][1], cube.F[f][2], cube.F[f][3]});
  ASSERT_EQ(p.V.size(), 26u);
  EXPECT_EQ(vcgext::WeldCoincidentVertices(p), 18);
  EXPECT_EQ(p.V.size(), 8u);
  for (size_t f = 1; f + 1 < p.F.size(); ++f)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(p.V[p.F[f + 1][k]], cube.V[cube.F[f][k]]) << f << " " << k;
  EXPECT_EQ(vcgext::WeldCoincidentVertices(p), 0);
}

// The polygon version: the cube's top (4, 5, 7, 6) cut along 4 -> v -> 5 into the triangle
// (4, 5, v) and the pentagon (4, v, 5, 7, 6), as a quad-dominant remesher leaves it: merged back.
TEST(RemoveDoublets, MergesATriangleAndAPentagonRoundAPolygonDoublet) {
  const auto cube = Cube();
  vcgext::PolyData p;
  p.V = cube.V;
  const int v = int(p.V.size());
  p.V.push_back(vcgext::Vec3(0.5, 0.3, 1));
  for (const auto& f : cube.F)
    if (f[0] != 4) p.F.push_back({f[0], f[1], f[2], f[3]});
  p.F.push_back({4, 5, v});
  p.F.push_back({4, v, 5, 7, 6});
  EXPECT_EQ(vcgext::RemoveDoublets(p), 1);
  ASSERT_EQ(p.F.size(), 6u);
  EXPECT_EQ(p.V.size(), 8u);
  std::vector<std::vector<int>> byCoordinates, expected;  // the merged face, by its corners' positions
  for (const auto& f : cube.F) expected.push_back({f[0], f[1], f[2], f[3]});
  for (const auto& f : p.F) {
    std::vector<int> c;
    for (int k : f) c.push_back(int(std::find(cube.V.begin(), cube.V.end(), p.V[k]) - cube.V.begin()));
    byCoordinates.push_back(c);
  }
  EXPECT_EQ(testsupport::CanonicalFaceSet(byCoordinates), testsupport::CanonicalFaceSet(expected));
  EXPECT_EQ(vcgext::RemoveDoublets(p), 0);
}
