// Tests for vcg_ext/core/indexed_mesh.h: the adjacency helpers against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "test_support.h"
#include "vcg_ext/core/indexed_mesh.h"

using vcgext::TriData;

namespace {
std::vector<std::pair<int, int>> BruteForceBoundary(const TriData& t) {
  std::multiset<std::pair<int, int>> he;
  for (const auto& f : t.F)
    for (int k = 0; k < 3; ++k) he.insert({f[k], f[(k + 1) % 3]});
  std::vector<std::pair<int, int>> out;
  for (const auto& f : t.F)
    for (int k = 0; k < 3; ++k)
      if (!he.count({f[(k + 1) % 3], f[k]})) out.push_back({f[k], f[(k + 1) % 3]});
  return out;
}
}  // namespace

// BoundaryHalfEdges: a closed sphere has none, an n x n grid 4n, and random holes (faces
// removed) give what a multiset of half-edges gives, in the same order.
TEST(IndexedMesh, BoundaryHalfEdgesMatchBruteForce) {
  EXPECT_TRUE(vcgext::BoundaryHalfEdges(testsupport::Icosphere(2)).empty());
  EXPECT_EQ(vcgext::BoundaryHalfEdges(testsupport::PlaneGrid(12, 12)).size(), 48u);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    TriData t = testsupport::Icosphere(2);
    std::shuffle(t.F.begin(), t.F.end(), rng);
    t.F.resize(t.F.size() - 1 - trial * 7);  // holes, some of them touching
    const auto got = vcgext::BoundaryHalfEdges(t);
    EXPECT_EQ(got, BruteForceBoundary(t)) << "trial " << trial;
    EXPECT_FALSE(got.empty());
  }
}
