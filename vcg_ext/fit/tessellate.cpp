/// \file tessellate.cpp
/// TessellateLimit: the welded, watertight tessellation of the limit surface (bake.h).
#include <algorithm>
#include <unordered_map>

#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/fit_internal.h"
#include "vcg_ext/fit/texel_space.h"

namespace vcgext {

using namespace fitdetail;

LimitTessellation TessellateLimit(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int N) {
  return TessellateLimit(ls, ctrl, std::vector<int>(size_t(std::max(ls.NumFaces(), 0)), N));
}

namespace {
// A point on a patch edge at fraction num/den of the canonical direction (lower control vertex
// id first), 0 < num < den.
struct EdgeFrac {
  int num, den;
  bool operator<(const EdgeFrac& o) const { return (long long)num * o.den < (long long)o.num * den; }
  bool operator==(const EdgeFrac& o) const { return (long long)num * o.den == (long long)o.num * den; }
};
struct EdgePoints {
  int n[2] = {0, 0};             // segment counts of the (up to two) patches on the edge
  std::vector<EdgeFrac> points;  // sorted union of their interior segment points
  int base = -1;                 // vertex id of points[0] (ids consecutive)
};
}  // namespace


LimitTessellation TessellateLimit(const LimitSurface& ls, const std::vector<Vec3>& ctrl,
                                  const std::vector<int>& segments) {
  LimitTessellation t;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || int(segments.size()) != nF) return t;
  for (int n : segments)
    if (n < 1) return t;
  t.N = segments[0];
  for (int n : segments)
    if (n != t.N) t.N = 0;
  // Edges: the union of the segment points of the patches on each side.
  std::unordered_map<std::uint64_t, EdgePoints> edges;
  for (int f = 0; f < nF; ++f)
    for (int e = 0; e < 4; ++e) {
      const int a = ls.FaceVertex(f, e), b = ls.FaceVertex(f, (e + 1) % 4);
      EdgePoints& ep = edges[a < b ? EdgeKey(a, b) : EdgeKey(b, a)];
      ep.n[ep.n[0] ? 1 : 0] = segments[f];
    }
  for (auto& kv : edges) {
    EdgePoints& ep = kv.second;
    for (int s = 0; s < 2; ++s)
      for (int m = 1; m < ep.n[s]; ++m) ep.points.push_back({m, ep.n[s]});
    std::sort(ep.points.begin(), ep.points.end());
    ep.points.erase(std::unique(ep.points.begin(), ep.points.end()), ep.points.end());
  }
  std::vector<int> cornerId(ls.NumVertices(), -1);
  auto addVertex = [&](int f, double u, double v) {
    t.face.push_back(f);
    t.uv.emplace_back(u, v);
    return int(t.face.size()) - 1;
  };
  auto addTri = [&](int f, int a, int b, int c) {
    t.mesh.F.push_back({a, b, c});
    t.triPatch.push_back(f);
  };
  std::vector<int> g;  // the patch's grid vertex ids, (N+1)²
  for (int f = 0; f < nF; ++f) {
    const int N = segments[f];
    g.assign(size_t(N + 1) * (N + 1), -1);
    const int cu[4] = {0, N, N, 0}, cvv[4] = {0, 0, N, N};
    int cv[4];
    for (int c = 0; c < 4; ++c) cv[c] = ls.FaceVertex(f, c);
    for (int c = 0; c < 4; ++c) {
      int& id = cornerId[cv[c]];
      if (id < 0) id = addVertex(f, double(cu[c]) / N, double(cvv[c]) / N);
      g[cvv[c] * (N + 1) + cu[c]] = id;
    }
    // side e: its edge, direction and the index range of the points between grid points
    EdgePoints* side[4];
    bool fwd[4];
    for (int e = 0; e < 4; ++e) {
      const int a = cv[e], b = cv[(e + 1) % 4];
      fwd[e] = a < b;
      EdgePoints& ep = edges[fwd[e] ? EdgeKey(a, b) : EdgeKey(b, a)];
      side[e] = &ep;
      if (ep.base < 0) {  // first patch on this edge: create its points in canonical order
        ep.base = int(t.face.size());
        for (const EdgeFrac& q : ep.points) {
          int i, j;
          SidePoint(e, fwd[e] ? q.num : q.den - q.num, q.den, &i, &j);
          addVertex(f, double(i) / q.den, double(j) / q.den);
        }
      }
      for (int m = 1; m < N; ++m) {
        const EdgeFrac q{fwd[e] ? m : N - m, N};
        const auto it = std::lower_bound(ep.points.begin(), ep.points.end(), q);
        int i, j;
        SidePoint(e, m, N, &i, &j);
        g[j * (N + 1) + i] = ep.base + int(it - ep.points.begin());
      }
    }
    for (int j = 1; j < N; ++j)
      for (int i = 1; i < N; ++i) g[j * (N + 1) + i] = addVertex(f, double(i) / N, double(j) / N);
    // Index in side e's point list of the side's grid point m (0..N; -1 / size() = corners).
    auto sideIndex = [&](int e, int m) {
      const EdgePoints& ep = *side[e];
      if (m == 0) return fwd[e] ? -1 : int(ep.points.size());
      if (m == N) return fwd[e] ? int(ep.points.size()) : -1;
      const EdgeFrac q{fwd[e] ? m : N - m, N};
      return int(std::lower_bound(ep.points.begin(), ep.points.end(), q) - ep.points.begin());
    };
    // Extra points of side e strictly between its grid points m and m+1, in side order.
    std::vector<int> extra[4];
    auto extras = [&](int e, int m, std::vector<int>& out) {
      out.clear();
      const int k0 = sideIndex(e, m), k1 = sideIndex(e, m + 1);
      if (k0 < k1)
        for (int k = k0 + 1; k < k1; ++k) out.push_back(side[e]->base + k);
      else
        for (int k = k0 - 1; k > k1; --k) out.push_back(side[e]->base + k);
    };
    std::vector<int> poly;
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) {
        const int v00 = g[j * (N + 1) + i], v10 = g[j * (N + 1) + i + 1];
        const int v11 = g[(j + 1) * (N + 1) + i + 1], v01 = g[(j + 1) * (N + 1) + i];
        for (auto& x : extra) x.clear();
        if (j == 0) extras(0, i, extra[0]);              // bottom, along e0
        if (i == N - 1) extras(1, j, extra[1]);          // right, along e1
        if (j == N - 1) extras(2, N - 1 - i, extra[2]);  // top, along e2
        if (i == 0) extras(3, N - 1 - j, extra[3]);      // left, along e3
        if (extra[0].empty() && extra[1].empty() && extra[2].empty() && extra[3].empty()) {
          addTri(f, v00, v10, v11);
          addTri(f, v00, v11, v01);
          continue;
        }
        // The cell as a polygon (counter-clockwise in (u,v)), fanned from a corner whose two
        // sides carry no extra points, else from a new vertex at the cell centre.
        const int corner[4] = {v00, v10, v11, v01};
        poly.clear();
        int start = -1;
        for (int c = 0; c < 4; ++c) {
          if (start < 0 && extra[c].empty() && extra[(c + 3) % 4].empty()) start = int(poly.size());
          poly.push_back(corner[c]);
          poly.insert(poly.end(), extra[c].begin(), extra[c].end());
        }
        const int n = int(poly.size());
        if (start >= 0) {
          for (int k = 1; k + 1 < n; ++k) addTri(f, poly[start], poly[(start + k) % n], poly[(start + k + 1) % n]);
        } else {
          const int c = addVertex(f, (i + 0.5) / N, (j + 0.5) / N);
          for (int k = 0; k < n; ++k) addTri(f, c, poly[k], poly[(k + 1) % n]);
        }
      }
  }
  const int nV = int(t.face.size());
  t.mesh.V.resize(nV);
  t.normal.resize(nV);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nV; ++v) {
    t.mesh.V[v] = fitdetail::LimitPointNormal(ls, ctrl, t.face[v], t.uv[v][0], t.uv[v][1], &t.normal[v]);
  }
  return t;
}

}  // namespace vcgext
