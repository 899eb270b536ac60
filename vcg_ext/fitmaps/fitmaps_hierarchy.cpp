/// \file fitmaps_hierarchy.cpp
/// Fast mode's vertex hierarchy (docs/fitmaps.md): level 0 is the mesh, each coarser level a
/// greedy cover of the one below; and the robust vertex normals every evaluation's frame uses.
#include "vcg_ext/fitmaps/fitmaps_eval.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <limits>

namespace vcgext::fitmaps_internal {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

/// Area-weighted normals; where they vanish (unreferenced vertex, faces cancelling at a
/// non-manifold vertex), the PCA normal of the 30 nearest vertices of the connected
/// neighbourhood; zero if that is undefined too (a single isolated vertex).
std::vector<Vec3> RobustNormals(const TriData& m, const Adjacency& vv, double rMax, int& fallbacks) {
  std::vector<Vec3> N = VertexNormals(m);
  std::vector<int> bad;
  for (size_t i = 0; i < N.size(); ++i)
    if (N[i].squaredNorm() == 0 && vv.Count(int(i)) > 0) bad.push_back(int(i));
  fallbacks = int(bad.size());
#pragma omp parallel
  {
    GatherScratch gs;
    std::vector<std::pair<int, double>> got;
#pragma omp for schedule(dynamic, 16)
    for (long b = 0; b < long(bad.size()); ++b) {
      const int i = bad[b];
      GatherMinimax(vv, m.V, i, rMax, gs, got, 30);
      if (got.size() < 2) continue;
      Vec3 c = Vec3::Zero();
      for (auto& [q, k] : got) c += m.V[q];
      c /= double(got.size());
      Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
      for (auto& [q, k] : got) C += (m.V[q] - c) * (m.V[q] - c).transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
      Vec3 n = es.eigenvectors().col(0);
      if (n.allFinite() && n.norm() > 0.5) N[i] = n.normalized();
    }
  }
  return N;
}

/// Level 0 of the hierarchy: the mesh; faces belong to the cluster of their first corner.
Level MakeFineLevel(const TriData& m, const Adjacency& vv, double totalArea) {
  Level lv;
  const int n = int(m.V.size());
  lv.adj = vv;
  lv.X = m.V;
  lv.W.assign(n, 1.0);
  lv.fineIdx.resize(n);
  lv.ofFine.resize(n);
  for (int i = 0; i < n; ++i) lv.fineIdx[i] = lv.ofFine[i] = i;
  lv.areaPerPoint = totalArea / std::max(1, n);
  return lv;
}

/// Cluster -> faces lists with cumulative areas (face f belongs to the cluster of F[f][0]).
void BuildClusterFaces(const TriData& m, const std::vector<double>& faceArea, Level& lv) {
  const int nc = int(lv.X.size());
  lv.faces.offs.assign(nc + 1, 0);
  for (const auto& f : m.F) ++lv.faces.offs[lv.ofFine[f[0]] + 1];
  for (int c = 0; c < nc; ++c) lv.faces.offs[c + 1] += lv.faces.offs[c];
  lv.faces.idx.resize(m.F.size());
  std::vector<int> fill(lv.faces.offs.begin(), lv.faces.offs.end() - 1);
  for (size_t f = 0; f < m.F.size(); ++f) lv.faces.idx[fill[lv.ofFine[m.F[f][0]]]++] = int(f);
  lv.faceCum.resize(m.F.size());
  lv.area.assign(nc, 0.0);
  for (int c = 0; c < nc; ++c) {
    double acc = 0;
    for (int k = lv.faces.offs[c]; k < lv.faces.offs[c + 1]; ++k) {
      acc += faceArea[lv.faces.idx[k]];
      lv.faceCum[k] = acc;
    }
    lv.area[c] = acc;
  }
}

/// Next coarser level: seeds greedily covering the level within `cover` (connected traversal,
/// so clusters never join separate components), every point assigned to its graph-nearest seed
/// (multi-source Dijkstra on edge lengths), clusters adjacent when any members are.
Level Coarsen(const Level& f, double cover) {
  const int n = int(f.X.size());
  std::vector<char> covered(n, 0);
  std::vector<int> seeds;
  GatherScratch gs;
  std::vector<std::pair<int, double>> got;
  for (int i = 0; i < n; ++i) {
    if (covered[i]) continue;
    seeds.push_back(i);
    GatherMinimax(f.adj, f.X, i, cover, gs, got);
    for (auto& [q, k] : got) covered[q] = 1;
  }
  std::vector<int> label(n, -1);
  std::vector<double> dist(n, kInf);
  std::vector<std::pair<double, int>> heap;
  auto cmp = std::greater<std::pair<double, int>>();
  for (int s = 0; s < int(seeds.size()); ++s) {
    dist[seeds[s]] = 0;
    label[seeds[s]] = s;
    heap.emplace_back(0.0, seeds[s]);
  }
  std::make_heap(heap.begin(), heap.end(), cmp);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), cmp);
    auto [d, q] = heap.back();
    heap.pop_back();
    if (d > dist[q]) continue;
    for (const int* it = f.adj.Begin(q); it != f.adj.End(q); ++it) {
      const double nd = d + (f.X[*it] - f.X[q]).norm();
      if (nd < dist[*it]) {
        dist[*it] = nd;
        label[*it] = label[q];
        heap.emplace_back(nd, *it);
        std::push_heap(heap.begin(), heap.end(), cmp);
      }
    }
  }
  Level c;
  const int nc = int(seeds.size());
  c.X.resize(nc);
  c.fineIdx.resize(nc);
  c.W.assign(nc, 0.0);
  for (int s = 0; s < nc; ++s) {
    c.X[s] = f.X[seeds[s]];
    c.fineIdx[s] = f.fineIdx[seeds[s]];
  }
  for (int i = 0; i < n; ++i) c.W[label[i]] += f.W[i];
  std::vector<std::vector<int>> nb(nc);
  for (int i = 0; i < n; ++i)
    for (const int* it = f.adj.Begin(i); it != f.adj.End(i); ++it)
      if (label[*it] != label[i]) nb[label[i]].push_back(label[*it]);
  c.adj.offs.assign(nc + 1, 0);
  for (int s = 0; s < nc; ++s) {
    auto& l = nb[s];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    c.adj.offs[s + 1] = c.adj.offs[s] + int(l.size());
  }
  for (auto& l : nb) c.adj.idx.insert(c.adj.idx.end(), l.begin(), l.end());
  c.ofFine.resize(f.ofFine.size());
  for (size_t v = 0; v < f.ofFine.size(); ++v) c.ofFine[v] = label[f.ofFine[v]];
  return c;
}

}  // namespace vcgext::fitmaps_internal
