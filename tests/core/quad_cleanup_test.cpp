// Doublet removal on foreign quad meshes (e.g. MeshLab's triangle pairing produces doublets).
#include <gtest/gtest.h>

#include <map>
#include <set>

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

}  // namespace
