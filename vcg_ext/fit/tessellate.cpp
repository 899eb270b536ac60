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
using EdgeTable = std::unordered_map<std::uint64_t, EdgePoints>;

// Whether `segments` has one count >= 1 per patch of a valid, non-empty surface.
bool SegmentsFit(const LimitSurface& ls, const std::vector<int>& segments) {
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || int(segments.size()) != nF) return false;
  for (int n : segments)
    if (n < 1) return false;
  return true;
}

// The segment count of every patch when they are all the same, else 0.
int CommonSegments(const std::vector<int>& segments) {
  int N = segments[0];
  for (int n : segments)
    if (n != N) N = 0;
  return N;
}

// Edges: the union of the segment points of the patches on each side.
EdgeTable CollectEdgePoints(const LimitSurface& ls, const std::vector<int>& segments) {
  EdgeTable edges;
  const int nF = ls.NumFaces();
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
  return edges;
}

// Adds the patches one by one to the tessellation: corner and edge vertices are shared with
// the neighbouring patches, interior vertices and triangles are the patch's own.
class PatchTessellator {
 public:
  PatchTessellator(const LimitSurface& ls, EdgeTable& edges, LimitTessellation& t)
      : ls_(ls), edges_(edges), t_(t), cornerId_(ls.NumVertices(), -1) {}

  // Patch f with N segments per side: its grid's vertices, then its cells' triangles.
  void AddPatch(int f, int N) {
    N_ = N;
    g_.assign(size_t(N + 1) * (N + 1), -1);
    AddCorners(f);
    AddSides(f);
    AddInterior(f);
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) TriangulateCell(f, i, j);
  }

 private:
  int AddVertex(int f, double u, double v) {
    t_.face.push_back(f);
    t_.uv.emplace_back(u, v);
    return int(t_.face.size()) - 1;
  }
  void AddTri(int f, int a, int b, int c) {
    t_.mesh.F.push_back({a, b, c});
    t_.triPatch.push_back(f);
  }

  // The grid's corners: one vertex per control vertex, made by its first patch.
  void AddCorners(int f) {
    const int N = N_;
    const int cu[4] = {0, N, N, 0}, cvv[4] = {0, 0, N, N};
    for (int c = 0; c < 4; ++c) cv_[c] = ls_.FaceVertex(f, c);
    for (int c = 0; c < 4; ++c) {
      int& id = cornerId_[cv_[c]];
      if (id < 0) id = AddVertex(f, double(cu[c]) / N, double(cvv[c]) / N);
      g_[cvv[c] * (N + 1) + cu[c]] = id;
    }
  }

  // Side e: its edge, direction and the index range of the points between grid points.
  void AddSides(int f) {
    const int N = N_;
    for (int e = 0; e < 4; ++e) {
      const int a = cv_[e], b = cv_[(e + 1) % 4];
      fwd_[e] = a < b;
      EdgePoints& ep = edges_[fwd_[e] ? EdgeKey(a, b) : EdgeKey(b, a)];
      side_[e] = &ep;
      if (ep.base < 0) AddEdgePoints(f, e, ep);
      for (int m = 1; m < N; ++m) {
        int i, j;
        SidePoint(e, m, N, &i, &j);
        g_[j * (N + 1) + i] = ep.base + SideIndex(e, m);
      }
    }
  }

  // First patch on this edge (its side e): create its points in canonical order.
  void AddEdgePoints(int f, int e, EdgePoints& ep) {
    ep.base = int(t_.face.size());
    for (const EdgeFrac& q : ep.points) {
      int i, j;
      SidePoint(e, fwd_[e] ? q.num : q.den - q.num, q.den, &i, &j);
      AddVertex(f, double(i) / q.den, double(j) / q.den);
    }
  }

  void AddInterior(int f) {
    const int N = N_;
    for (int j = 1; j < N; ++j)
      for (int i = 1; i < N; ++i) g_[j * (N + 1) + i] = AddVertex(f, double(i) / N, double(j) / N);
  }

  // Index in side e's point list of the side's grid point m (0..N; -1 / size() = corners).
  int SideIndex(int e, int m) const {
    const int N = N_;
    const EdgePoints& ep = *side_[e];
    if (m == 0) return fwd_[e] ? -1 : int(ep.points.size());
    if (m == N) return fwd_[e] ? int(ep.points.size()) : -1;
    const EdgeFrac q{fwd_[e] ? m : N - m, N};
    return int(std::lower_bound(ep.points.begin(), ep.points.end(), q) - ep.points.begin());
  }

  // Extra points of side e strictly between its grid points m and m+1, in side order.
  void Extras(int e, int m, std::vector<int>& out) const {
    out.clear();
    const int k0 = SideIndex(e, m), k1 = SideIndex(e, m + 1);
    if (k0 < k1)
      for (int k = k0 + 1; k < k1; ++k) out.push_back(side_[e]->base + k);
    else
      for (int k = k0 - 1; k > k1; --k) out.push_back(side_[e]->base + k);
  }

  // The extra points on the sides of cell (i,j) that lie on the patch border; false if none.
  bool CellExtras(int i, int j) {
    const int N = N_;
    for (auto& x : extra_) x.clear();
    if (j == 0) Extras(0, i, extra_[0]);              // bottom, along e0
    if (i == N - 1) Extras(1, j, extra_[1]);          // right, along e1
    if (j == N - 1) Extras(2, N - 1 - i, extra_[2]);  // top, along e2
    if (i == 0) Extras(3, N - 1 - j, extra_[3]);      // left, along e3
    return !(extra_[0].empty() && extra_[1].empty() && extra_[2].empty() && extra_[3].empty());
  }

  // Cell (i,j): two triangles, or a fan when its border sides carry extra points.
  void TriangulateCell(int f, int i, int j) {
    const int N = N_;
    const int v00 = g_[j * (N + 1) + i], v10 = g_[j * (N + 1) + i + 1];
    const int v11 = g_[(j + 1) * (N + 1) + i + 1], v01 = g_[(j + 1) * (N + 1) + i];
    if (!CellExtras(i, j)) {
      AddTri(f, v00, v10, v11);
      AddTri(f, v00, v11, v01);
      return;
    }
    const int corner[4] = {v00, v10, v11, v01};
    FanCell(f, i, j, corner);
  }

  // The cell as a polygon (counter-clockwise in (u,v)), fanned from a corner whose two
  // sides carry no extra points, else from a new vertex at the cell centre.
  void FanCell(int f, int i, int j, const int (&corner)[4]) {
    const int N = N_;
    poly_.clear();
    int start = -1;
    for (int c = 0; c < 4; ++c) {
      if (start < 0 && extra_[c].empty() && extra_[(c + 3) % 4].empty()) start = int(poly_.size());
      poly_.push_back(corner[c]);
      poly_.insert(poly_.end(), extra_[c].begin(), extra_[c].end());
    }
    const int n = int(poly_.size());
    if (start >= 0) {
      for (int k = 1; k + 1 < n; ++k) AddTri(f, poly_[start], poly_[(start + k) % n], poly_[(start + k + 1) % n]);
    } else {
      const int c = AddVertex(f, (i + 0.5) / N, (j + 0.5) / N);
      for (int k = 0; k < n; ++k) AddTri(f, c, poly_[k], poly_[(k + 1) % n]);
    }
  }

  const LimitSurface& ls_;
  EdgeTable& edges_;
  LimitTessellation& t_;
  std::vector<int> cornerId_;  // tessellation vertex of each control vertex, or -1
  // The current patch: segments per side, corner control vertices, sides and their direction,
  // grid vertex ids ((N+1)²), a cell's extra side points and polygon.
  int N_ = 0;
  int cv_[4] = {-1, -1, -1, -1};
  EdgePoints* side_[4] = {nullptr, nullptr, nullptr, nullptr};
  bool fwd_[4] = {false, false, false, false};
  std::vector<int> g_;
  std::vector<int> extra_[4];
  std::vector<int> poly_;
};

// The limit point and normal of every vertex (parallel).
void EvaluateVertices(const LimitSurface& ls, const std::vector<Vec3>& ctrl, LimitTessellation& t) {
  const int nV = int(t.face.size());
  t.mesh.V.resize(nV);
  t.normal.resize(nV);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nV; ++v) {
    t.mesh.V[v] = fitdetail::LimitPointNormal(ls, ctrl, t.face[v], t.uv[v][0], t.uv[v][1], &t.normal[v]);
  }
}
}  // namespace


LimitTessellation TessellateLimit(const LimitSurface& ls, const std::vector<Vec3>& ctrl,
                                  const std::vector<int>& segments) {
  LimitTessellation t;
  if (!SegmentsFit(ls, segments)) return t;
  t.N = CommonSegments(segments);
  EdgeTable edges = CollectEdgePoints(ls, segments);
  PatchTessellator patches(ls, edges, t);
  for (int f = 0; f < ls.NumFaces(); ++f) patches.AddPatch(f, segments[f]);
  EvaluateVertices(ls, ctrl, t);
  return t;
}

}  // namespace vcgext
