/// \file union_find.h
/// Disjoint sets over the indices 0 .. n-1: connected pieces of a cage, fans of corners around a
/// vertex, sheets at a non-manifold vertex. One implementation for all of them (it replaced four
/// copies). vcglib's `vcg::DisjointSet` keys its elements by pointer through a hash map; the
/// callers here have dense indices, so this is the array version (path halving, no ranks).
#pragma once

#include <numeric>
#include <vector>

namespace vcgext {

/// `Unite(a, b)` hangs a's root under b's, so which element is a set's root is fixed by the order
/// of the unions; callers that use roots as labels (the first fan keeps its vertex,
/// `SplitNonManifoldVertices`) rely on that, and their outputs do not depend on anything else.
class UnionFind {
 public:
  explicit UnionFind(int n = 0) { Reset(n); }
  /// n singletons again (reuses the storage).
  void Reset(int n) {
    p_.resize(size_t(n));
    std::iota(p_.begin(), p_.end(), 0);
  }
  int Find(int x) {
    while (p_[size_t(x)] != x) x = p_[size_t(x)] = p_[size_t(p_[size_t(x)])];
    return x;
  }
  void Unite(int a, int b) {
    const int rb = Find(b);
    p_[size_t(Find(a))] = rb;
  }

 private:
  std::vector<int> p_;
};

}  // namespace vcgext
