// UnionFind (vcg_ext/core/union_find.h) against a brute-force partition: random unions on n
// elements, the sets compared with the connected components of the same pairs found by flooding.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "vcg_ext/core/union_find.h"

namespace {

// component label per element, by repeated relaxation (labels = the smallest member).
std::vector<int> FloodComponents(int n, const std::vector<std::pair<int, int>>& pairs) {
  std::vector<int> label(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) label[size_t(i)] = i;
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& [a, b] : pairs) {
      const int m = std::min(label[size_t(a)], label[size_t(b)]);
      for (int x : {a, b})
        if (label[size_t(x)] != m) label[size_t(x)] = m, changed = true;
    }
  }
  return label;
}

TEST(UnionFind, PartitionMatchesFloodedComponents) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 1 + int(rng() % 200);
    std::vector<std::pair<int, int>> pairs(rng() % size_t(n));
    for (auto& p : pairs) p = {int(rng() % size_t(n)), int(rng() % size_t(n))};
    vcgext::UnionFind uf(n);
    for (const auto& [a, b] : pairs) uf.Unite(a, b);
    const std::vector<int> label = FloodComponents(n, pairs);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        ASSERT_EQ(uf.Find(i) == uf.Find(j), label[size_t(i)] == label[size_t(j)])
            << "trial " << trial << ": " << i << ", " << j;
  }
}

TEST(UnionFind, UniteHangsTheFirstRootUnderTheSecond) {
  vcgext::UnionFind uf(4);
  uf.Unite(0, 1);
  EXPECT_EQ(uf.Find(0), 1);
  uf.Unite(1, 3);
  EXPECT_EQ(uf.Find(0), 3);
  EXPECT_EQ(uf.Find(2), 2);
  uf.Reset(3);  // singletons again
  for (int i = 0; i < 3; ++i) EXPECT_EQ(uf.Find(i), i);
}

}  // namespace
