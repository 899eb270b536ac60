#include "vcg_ext/core/memory.h"
#include "vcg_ext/fit/bake.h"


#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <unordered_map>

#include "vcg_ext/core/progress.h"
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "vcg_ext/fit/fit_internal.h"

namespace vcgext {

namespace {
using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
inline std::uint64_t EdgeKey(int a, int b) {
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}
}  // namespace

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
// (u,v) numerators (over den) of the point at edge fraction p/den of side e of a patch, going
// around the patch: e0 c0->c1 (v=0), e1 c1->c2 (u=1), e2 c2->c3 (v=1), e3 c3->c0 (u=0).
void SidePoint(int e, int p, int den, int* i, int* j) {
  switch (e) {
    case 0: *i = p; *j = 0; break;
    case 1: *i = den; *j = p; break;
    case 2: *i = den - p; *j = den; break;
    default: *i = 0; *j = den - p; break;
  }
}
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

std::vector<double> SignedDistanceToReference(const std::vector<Vec3>& pts, const EmbreeScene& ref, double maxDist) {
  std::vector<double> d(pts.size(), maxDist);
  const auto fn = FaceNormals(ref.Mesh());
#pragma omp parallel
  {
    int hint = -1;  // the previous point's face (ClosestPoint's hint: neighbouring points)
#pragma omp for schedule(static)
    for (long i = 0; i < long(pts.size()); ++i) {
      EmbreeScene::Hit h = ref.ClosestPoint(pts[i], maxDist, hint);
      if (!h.valid) continue;
      hint = h.face;
      Vec3 dv = pts[i] - h.point;
      double s = dv.dot(fn[h.face]) < 0 ? -1.0 : 1.0;
      d[i] = s * dv.norm();
    }
  }
  return d;
}

int AutoTextureResolution(int referenceVertices, int patches) {
  if (patches <= 0) return kMinAutoTextureResolution;
  return std::max(kMinAutoTextureResolution, int(std::lround(std::sqrt(double(referenceVertices) / patches))));
}

double AutoTextureBudget(int referenceVertices, int patches) {
  return std::max(double(referenceVertices),
                  double(kMinAutoTextureResolution) * kMinAutoTextureResolution * std::max(patches, 0));
}

long long DisplacementAtlas::Samples() const {
  long long n = 0;
  for (int r : tileR) n += (long long)r * r;
  return n;
}

void UniformAtlasLayout(DisplacementAtlas& a, int F, int R) {
  a.adaptive = false;
  a.R = R;
  a.cols = std::max(1, int(std::ceil(std::sqrt(double(F)))));
  a.rows = (F + a.cols - 1) / a.cols;
  a.width = a.cols * R;
  a.height = a.rows * R;
  a.tileR.assign(F, R);
  a.tileX.resize(F);
  a.tileY.resize(F);
  for (int f = 0; f < F; ++f) {
    a.tileX[f] = (f % a.cols) * R;
    a.tileY[f] = (f / a.cols) * R;
  }
  a.disp.assign(size_t(a.width) * a.height, 0.f);
}

void AdaptiveAtlasLayout(DisplacementAtlas& a, const std::vector<int>& tileR) {
  const int F = int(tileR.size());
  a.adaptive = true;
  a.cols = a.rows = 0;
  a.tileR = tileR;
  a.tileX.assign(F, 0);
  a.tileY.assign(F, 0);
  a.R = 0;
  long long area = 0;
  for (int r : tileR) {
    a.R = std::max(a.R, r);
    area += (long long)r * r;
  }
  // Shelf packing, tallest tiles first (ties by patch index: deterministic).
  std::vector<int> order(F);
  for (int f = 0; f < F; ++f) order[f] = f;
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return tileR[x] > tileR[y]; });
  a.width = std::max(a.R, int(std::ceil(std::sqrt(double(area)))));
  int x = 0, y = 0, shelf = 0;
  for (int f : order) {
    if (x + tileR[f] > a.width) {
      y += shelf;
      x = 0;
      shelf = 0;
    }
    a.tileX[f] = x;
    a.tileY[f] = y;
    x += tileR[f];
    shelf = std::max(shelf, tileR[f]);
  }
  a.height = y + shelf;
  a.disp.assign(size_t(a.width) * a.height, 0.f);
}

std::vector<int> AdaptiveTileResolutions(const std::vector<double>& patchArea, const std::vector<double>& patchVertices,
                                         double budget) {
  const int F = int(patchArea.size());
  constexpr int kLevels = 6;  // T = 2, 4, …, 64: tiles of 3 .. 65 texels per side
  std::vector<int> R(F, 3);
  if (F == 0 || int(patchVertices.size()) != F) return R;
  // Error model: a reference vertex on patch f is off the bilinear displaced layer by about the
  // texel spacing √(area_f)/T_f (measured on bunny00: the RMS per patch grows linearly with the
  // spacing), so the squared error summed over the reference vertices is Σ_f W_f / T_f² with
  // W_f = vertices_f · area_f, to minimize under Σ (T_f+1)² <= budget: a multiple-choice
  // knapsack. Every patch pays for its 3×3 tile first; (T+1)² − 9 = 8·c with
  // c = 0, 2, 9, 35, 135, 527 extra units of 8 texels.
  std::vector<double> W(F);
  for (int f = 0; f < F; ++f) W[f] = std::max(patchVertices[f], 0.0) * std::max(patchArea[f], 0.0);
  int extra[kLevels];
  double err[kLevels];
  for (int k = 0; k < kLevels; ++k) {
    const int t = 2 << k;
    extra[k] = ((t + 1) * (t + 1) - 9) / 8;
    err[k] = 1.0 / (double(t) * t);
  }
  const double spare = (budget - 9.0 * F) / 8.0;
  if (!(spare >= 1)) return R;  // no room beyond the smallest tiles
  const long long units = (long long)std::min(spare, double(extra[kLevels - 1]) * F);
  std::vector<int> level(F, 0);
  if (double(F) * double(units + 1) <= 4e7) {
    // Exact: dynamic programming over the spare units (bunny00: 379 × 4.3k cells).
    const int S = int(units);
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> best(S + 1, inf), next(S + 1);
    best[0] = 0;
    std::vector<std::uint8_t> choice(size_t(F) * (S + 1), 0);
    for (int f = 0; f < F; ++f) {
      std::fill(next.begin(), next.end(), inf);
      std::uint8_t* ch = choice.data() + size_t(f) * (S + 1);
      for (int k = 0; k < kLevels; ++k) {
        const double e = W[f] * err[k];
        for (int s = extra[k]; s <= S; ++s) {
          const double v = best[s - extra[k]] + e;
          if (v < next[s]) {  // ties: the smaller tile (k ascending)
            next[s] = v;
            ch[s] = std::uint8_t(k);
          }
        }
      }
      best.swap(next);
    }
    int s = int(std::min_element(best.begin(), best.end()) - best.begin());
    for (int f = F - 1; f >= 0; --f) {
      level[f] = choice[size_t(f) * (S + 1) + s];
      s -= extra[level[f]];
    }
  } else {
    // Many patches: Lagrangian relaxation (each patch minimizes W·err + λ·extra on its own; the
    // smallest λ that fits, by bisection), then the best upgrades that still fit. Optimal up to
    // the leftover of one knapsack step, which is small against a budget this large.
    double maxW = 0;
    for (double w : W) maxW = std::max(maxW, w);
    auto choose = [&](double lambda, std::vector<int>& out) {
      long long n = 0;
      for (int f = 0; f < F; ++f) {
        int bk = 0;
        for (int k = 1; k < kLevels; ++k)
          if (W[f] * err[k] + lambda * extra[k] < W[f] * err[bk] + lambda * extra[bk]) bk = k;
        out[f] = bk;
        n += extra[bk];
      }
      return n;
    };
    std::vector<int> trial(F);
    double lo = std::log(std::max(maxW, 1e-300)) - 80, hi = std::log(std::max(maxW, 1e-300)) + 5;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (choose(std::exp(mid), trial) <= units ? hi : lo) = mid;
    }
    long long used = choose(std::exp(hi), level);
    for (;;) {
      int bf = -1;
      double bestRate = 0;
      for (int f = 0; f < F; ++f) {
        const int k = level[f];
        if (k + 1 >= kLevels || used + extra[k + 1] - extra[k] > units) continue;
        const double rate = W[f] * (err[k] - err[k + 1]) / (extra[k + 1] - extra[k]);
        if (rate > bestRate) { bestRate = rate; bf = f; }
      }
      if (bf < 0) break;
      used += extra[level[bf] + 1] - extra[level[bf]];
      ++level[bf];
    }
  }
  for (int f = 0; f < F; ++f) R[f] = (2 << level[f]) + 1;
  return R;
}

std::vector<double> PatchVertexCounts(const LimitTessellation& t, int patches, const TriData& ref) {
  std::vector<double> n(std::max(patches, 0), 0.0);
  const EmbreeScene s(t.mesh);
  if (!s.Ok()) return n;
  std::vector<int> owner(ref.V.size(), -1);
#pragma omp parallel
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long v = 0; v < long(ref.V.size()); ++v) {
      const EmbreeScene::Hit h = s.ClosestPoint(ref.V[v], std::numeric_limits<double>::infinity(), hint);
      if (h.valid) hint = h.face;
      if (h.valid && h.face < int(t.triPatch.size())) owner[v] = t.triPatch[h.face];
    }
  }
  for (int o : owner)
    if (o >= 0 && o < patches) n[o] += 1;
  return n;
}

std::vector<double> PatchAreas(const LimitTessellation& t, int patches) {
  std::vector<double> area(std::max(patches, 0), 0.0);
  for (size_t k = 0; k < t.mesh.F.size() && k < t.triPatch.size(); ++k) {
    const auto& f = t.mesh.F[k];
    const int p = t.triPatch[k];
    if (p < 0 || p >= patches) continue;
    area[p] += 0.5 * (t.mesh.V[f[1]] - t.mesh.V[f[0]]).cross(t.mesh.V[f[2]] - t.mesh.V[f[0]]).norm();
  }
  return area;
}

namespace {
// The bilinear texture filter of a tile with T texel intervals per side (texel (i,j) at
// (u,v) = (i/T, j/T)): the cell's lower texel and the weights of texels (i,j), (i+1,j), (i,j+1),
// (i+1,j+1). DisplacedSurface and the texel fit must filter identically.
struct TileCell {
  int i, j;
  double w[4];
};
TileCell CellAt(const Eigen::Vector2d& uv, int T) {
  const double x = std::clamp(uv[0], 0.0, 1.0) * T, y = std::clamp(uv[1], 0.0, 1.0) * T;
  TileCell c;
  c.i = std::min(int(x), T - 1);
  c.j = std::min(int(y), T - 1);
  const double fx = x - c.i, fy = y - c.j;
  c.w[0] = (1 - fx) * (1 - fy);
  c.w[1] = fx * (1 - fy);
  c.w[2] = (1 - fx) * fy;
  c.w[3] = fx * fy;
  return c;
}

// 16-bit quantization over the tiles actually used: disp ≈ offset + scale · q16.
void Quantize(DisplacementAtlas& a) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int f = 0; f < a.Patches(); ++f)
    for (int j = 0; j < a.tileR[f]; ++j)
      for (int i = 0; i < a.tileR[f]; ++i) {
        double d = a.disp[a.Pixel(f, i, j)];
        lo = std::min(lo, d);
        hi = std::max(hi, d);
      }
  a.offset = lo;
  a.scale = hi > lo ? (hi - lo) / 65535.0 : 0.0;
  a.q16.assign(a.disp.size(), 0);
  for (size_t k = 0; k < a.disp.size(); ++k)
    if (a.scale > 0)
      a.q16[k] = std::uint16_t(std::clamp(std::lround((a.disp[k] - lo) / a.scale), 0L, 65535L));
}

// The free values of a seamless atlas: one unknown per surface point that some tile's texel
// stands for exactly — control vertices (tile corners), the texels of each shared edge at the
// coarser of its two tiles' resolutions, tile interiors. Every texel is one unknown or (a finer
// tile's extra edge texel) the linear interpolation of two neighbouring edge unknowns.
class TexelSpace {
 public:
  struct Term {
    int id[2];
    double w[2];
    int n;
  };
  TexelSpace(const LimitSurface& ls, const DisplacementAtlas& a) : a_(a) {
    const int nF = ls.NumFaces();
    std::unordered_map<std::uint64_t, std::pair<int, int>> edge;  // key -> (intervals, first knot id)
    for (int f = 0; f < nF; ++f)
      for (int e = 0; e < 4; ++e) {
        const int x = ls.FaceVertex(f, e), y = ls.FaceVertex(f, (e + 1) % 4);
        auto it = edge.emplace(x < y ? EdgeKey(x, y) : EdgeKey(y, x), std::make_pair(a.tileR[f] - 1, -1)).first;
        it->second.first = std::min(it->second.first, a.tileR[f] - 1);
      }
    std::vector<int> corner(ls.NumVertices(), -1);
    offset_.resize(nF + 1, 0);
    for (int f = 0; f < nF; ++f) offset_[f + 1] = offset_[f] + a.tileR[f] * a.tileR[f];
    terms_.resize(offset_[nF]);
    int next = 0;
    for (int f = 0; f < nF; ++f) {
      const int T = a.tileR[f] - 1;
      int cv[4];
      for (int c = 0; c < 4; ++c) {
        cv[c] = ls.FaceVertex(f, c);
        if (corner[cv[c]] < 0) corner[cv[c]] = next++;
      }
      const int cu[4] = {0, T, T, 0}, cvv[4] = {0, 0, T, T};
      for (int c = 0; c < 4; ++c) terms_[offset_[f] + cvv[c] * (T + 1) + cu[c]] = {{corner[cv[c]], 0}, {1, 0}, 1};
      for (int e = 0; e < 4; ++e) {
        const int x = cv[e], y = cv[(e + 1) % 4];
        const bool fwd = x < y;
        auto& ed = edge[fwd ? EdgeKey(x, y) : EdgeKey(y, x)];
        const int Te = ed.first, k = T / Te;  // powers of two: Te divides T
        if (ed.second < 0) {
          ed.second = next;
          next += Te - 1;
        }
        // knot q (0..Te) of the canonical direction: a corner or an edge unknown
        auto knot = [&](int q) {
          if (q == 0) return corner[std::min(x, y)];
          if (q == Te) return corner[std::max(x, y)];
          return ed.second + q - 1;
        };
        for (int m = 1; m < T; ++m) {
          const int c = fwd ? m : T - m;  // canonical position, units 1/T
          int i = 0, j = 0;
          SidePoint(e, m, T, &i, &j);
          Term& t = terms_[offset_[f] + j * (T + 1) + i];
          if (c % k == 0) {
            t = {{knot(c / k), 0}, {1, 0}, 1};
          } else {
            const double w = double(c % k) / k;
            t = {{knot(c / k), knot(c / k + 1)}, {1 - w, w}, 2};
          }
        }
      }
      for (int j = 1; j < T; ++j)
        for (int i = 1; i < T; ++i) terms_[offset_[f] + j * (T + 1) + i] = {{next++, 0}, {1, 0}, 1};
    }
    n_ = next;
  }
  int NumUnknowns() const { return n_; }
  const Term& At(int f, int i, int j) const { return terms_[offset_[f] + j * a_.tileR[f] + i]; }
  // Unknowns from the texels that stand for them exactly (the mean over the tiles sharing one).
  Eigen::VectorXd Gather(const DisplacementAtlas& a) const {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(n_), cnt = Eigen::VectorXd::Zero(n_);
    ForEach([&](int f, int i, int j, const Term& t) {
      if (t.n != 1) return;
      sum[t.id[0]] += a.disp[a.Pixel(f, i, j)];
      cnt[t.id[0]] += 1;
    });
    return sum.cwiseQuotient(cnt.cwiseMax(1.0));
  }
  // Writes every texel of every tile from the unknowns.
  void Scatter(const Eigen::VectorXd& d, DisplacementAtlas& a) const {
    ForEach([&](int f, int i, int j, const Term& t) {
      double v = 0;
      for (int q = 0; q < t.n; ++q) v += t.w[q] * d[t.id[q]];
      a.disp[a.Pixel(f, i, j)] = float(v);
    });
  }

 private:
  template <class Fn>
  void ForEach(Fn fn) const {
    for (int f = 0; f + 1 < int(offset_.size()); ++f)
      for (int j = 0; j < a_.tileR[f]; ++j)
        for (int i = 0; i < a_.tileR[f]; ++i) fn(f, i, j, At(f, i, j));
  }
  const DisplacementAtlas& a_;
  std::vector<size_t> offset_;
  std::vector<Term> terms_;
  int n_ = 0;
};

// The atlas's tile sizes are a valid layout for a surface of nF patches: one tile per patch,
// inside the image, and (for seamless edges) 2^k+1 texels when they differ.
bool LayoutOk(const DisplacementAtlas& a, int nF) {
  if (a.Patches() != nF || int(a.tileX.size()) != nF || int(a.tileY.size()) != nF || a.width < 1 || a.height < 1 ||
      a.disp.size() != size_t(a.width) * a.height)
    return false;
  bool uniform = true;
  for (int f = 0; f < nF; ++f) {
    const int r = a.tileR[f];
    if (r < 2 || a.tileX[f] < 0 || a.tileY[f] < 0 || a.tileX[f] + r > a.width || a.tileY[f] + r > a.height)
      return false;
    uniform = uniform && r == a.tileR[0];
  }
  if (!uniform)  // mixed sizes must nest: every r−1 a power of two
    for (int r : a.tileR)
      if (((r - 1) & (r - 2)) != 0) return false;
  return true;
}
}  // namespace

DisplacementAtlas BakeDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                   const EmbreeScene& scene, int R, double maxDist, bool normalMap) {
  DisplacementAtlas a;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || R < 2) return a;
  UniformAtlasLayout(a, nF, R);
  BakeDisplacement(ls, ctrl, ref, scene, maxDist, normalMap, a);
  return a;
}

void BakeDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                      const EmbreeScene& scene, double maxDist, bool normalMap, DisplacementAtlas& a) {
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || !LayoutOk(a, nF)) {
    a = DisplacementAtlas();
    return;
  }
  a.disp.assign(size_t(a.width) * a.height, 0.f);
  a.normalRGB.clear();
  if (normalMap) a.normalRGB.assign(size_t(a.width) * a.height * 3, 128);
  std::vector<Vec3> vn;
  if (normalMap) vn = VertexNormals(ref);
  const std::vector<Vec3> refN = FaceNormals(ref);
  int misses = 0;
#pragma omp parallel for schedule(dynamic, 8) reduction(+ : misses)
  for (int f = 0; f < nF; ++f) {
    const int R = a.tileR[f];
    for (int j = 0; j < R; ++j)
      for (int i = 0; i < R; ++i) {
        Vec3 n;
        const Vec3 P = fitdetail::LimitPointNormal(ls, ctrl, f, double(i) / (R - 1), double(j) / (R - 1), &n);
        double d = 0;
        EmbreeScene::Hit h;
        if (n.squaredNorm() > 0) h = fitdetail::IntersectLineOriented(scene, refN, P, n, maxDist);
        if (h.valid) {
          d = h.t;
        } else {
          ++misses;
          h = scene.ClosestPoint(P, maxDist);
          if (h.valid) d = (h.point - P).dot(n);
        }
        const size_t px = a.Pixel(f, i, j);
        a.disp[px] = float(d);
        if (normalMap) {
          Vec3 nn = n;
          if (h.valid) {
            const auto& t = ref.F[h.face];
            nn = (1 - h.u - h.v) * vn[t[0]] + h.u * vn[t[1]] + h.v * vn[t[2]];
            if (nn.norm() > 0) nn.normalize();
          }
          for (int c = 0; c < 3; ++c)
            a.normalRGB[px * 3 + c] = std::uint8_t(std::clamp(std::lround((nn[c] + 1) * 0.5 * 255), 0L, 255L));
        }
      }
  }
  a.misses = misses;
  // One value per surface point: shared texels agree, finer edges follow coarser neighbours.
  const TexelSpace space(ls, a);
  space.Scatter(space.Gather(a), a);
  Quantize(a);
  // Wedge UVs at the corner texels' centres; v up (OpenGL / OBJ / MeshLab), image row 0 on top.
  a.wedgeUV.resize(nF);
  const int cu[4] = {0, 1, 1, 0}, cvv[4] = {0, 0, 1, 1};
  for (int f = 0; f < nF; ++f) {
    const int R = a.tileR[f];
    for (int c = 0; c < 4; ++c) {
      double x = a.tileX[f] + 0.5 + cu[c] * (R - 1), y = a.tileY[f] + 0.5 + cvv[c] * (R - 1);
      a.wedgeUV[f][c] = Eigen::Vector2d(x / a.width, 1.0 - y / a.height);
    }
  }
}

namespace {
// Segments per side of the displaced layer's patches: the tile's texel intervals, at least
// minSegments.
std::vector<int> DisplacedSegments(const DisplacementAtlas& a, int minSegments) {
  std::vector<int> n(a.tileR.size());
  for (size_t f = 0; f < n.size(); ++f) n[f] = std::max(a.tileR[f] - 1, minSegments);
  return n;
}

// The displaced layer as a linear function of the texel unknowns (TexelSpace): its base
// tessellation (what DisplacedSurface displaces) and, per base vertex, the weights of the
// unknowns in the bilinear filter of its patch's tile (4 texels, each 1 or 2 unknowns).
class DisplacedModel {
 public:
  static constexpr int kMaxTerms = 8;
  DisplacedModel(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const DisplacementAtlas& a, int minSegments)
      : space_(ls, a) {
    base_ = TessellateLimit(ls, ctrl, DisplacedSegments(a, minSegments));
    const int nB = NumBase();
    bt_.resize(nB);
    bw_.resize(nB);
    bn_.assign(nB, 0);
    for (int k = 0; k < nB; ++k) {
      const int f = base_.face[k];
      const TileCell c = CellAt(base_.uv[k], a.tileR[f] - 1);
      const int ti[4] = {c.i, c.i + 1, c.i, c.i + 1}, tj[4] = {c.j, c.j, c.j + 1, c.j + 1};
      for (int q = 0; q < 4; ++q) {
        if (c.w[q] == 0) continue;
        const TexelSpace::Term& t = space_.At(f, ti[q], tj[q]);
        for (int s = 0; s < t.n; ++s) {
          int slot = 0;
          while (slot < bn_[k] && bt_[k][slot] != t.id[s]) ++slot;
          if (slot == bn_[k]) {
            bt_[k][slot] = t.id[s];
            bw_[k][slot] = 0;
            ++bn_[k];
          }
          bw_[k][slot] += c.w[q] * t.w[s];
        }
      }
    }
  }
  const LimitTessellation& Base() const { return base_; }
  const TexelSpace& Space() const { return space_; }
  int NumUnknowns() const { return space_.NumUnknowns(); }
  int NumBase() const { return int(base_.mesh.V.size()); }
  int Terms(int k) const { return bn_[k]; }
  const std::array<int, kMaxTerms>& Unknowns(int k) const { return bt_[k]; }
  const std::array<double, kMaxTerms>& Weights(int k) const { return bw_[k]; }
  double Displacement(int k, const Eigen::VectorXd& d) const {
    double s = 0;
    for (int q = 0; q < bn_[k]; ++q) s += bw_[k][q] * d[bt_[k][q]];
    return s;
  }
  TriData Mesh(const Eigen::VectorXd& d) const {
    TriData m;
    m.F = base_.mesh.F;
    m.V.resize(NumBase());
    for (int k = 0; k < NumBase(); ++k) m.V[k] = base_.mesh.V[k] + Displacement(k, d) * base_.normal[k];
    return m;
  }

 private:
  TexelSpace space_;
  LimitTessellation base_;
  std::vector<std::array<int, kMaxTerms>> bt_;
  std::vector<std::array<double, kMaxTerms>> bw_;
  std::vector<int> bn_;
};
}  // namespace

DisplacementFitStats FitDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                     int minSegments, double maxDist, const DisplacementFitParams& p,
                                     DisplacementAtlas& a) {
  DisplacementFitStats st;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || ref.V.empty() || p.iterations < 1 || !(p.anchorWeight > 0) || !(maxDist > 0))
    return st;
  // the atlas must be a layout of this surface (BakeDisplacement's)
  if (!LayoutOk(a, nF)) return st;
  const DisplacedModel model(ls, ctrl, a, minSegments);
  const LimitTessellation& base = model.Base();
  const int nX = model.NumUnknowns();
  // Point-sampled (ray) values: the anchor of every texel.
  const Eigen::VectorXd d0 = model.Space().Gather(a);
  Eigen::VectorXd d = d0;
  const int nR = int(ref.V.size());
  constexpr int kMaxRow = 3 * DisplacedModel::kMaxTerms;  // 3 triangle corners
  std::vector<std::array<int, kMaxRow>> rowIdx(nR);
  std::vector<std::array<double, kMaxRow>> rowW(nR);
  std::vector<int> rowLen(nR);
  Eigen::VectorXd rhs0(nR), dist(nR);
  Eigen::VectorXd best = d;
  double bestRms = std::numeric_limits<double>::infinity();
  for (int it = 0; it <= p.iterations; ++it) {
    // Foot points on the current displaced mesh: exactly the reported error's closest points.
    const TriData dm = model.Mesh(d);
    EmbreeScene scene(dm);
    if (!scene.Ok()) break;
#pragma omp parallel
    {
      int hint = -1;
#pragma omp for schedule(static)
      for (int r = 0; r < nR; ++r) {
        const Vec3& x = ref.V[r];
        const EmbreeScene::Hit h = scene.ClosestPoint(x, std::numeric_limits<double>::infinity(), hint);
        if (h.valid) hint = h.face;
        rowLen[r] = 0;
        dist[r] = h.valid ? (h.point - x).norm() : 0.0;
        // no row for reference parts farther than the bake's range (not covered by the control
        // mesh, outliers): the texels must not be pulled there (they stay within ±maxDist)
        if (!h.valid || dist[r] > maxDist) continue;
        const auto& tri = dm.F[h.face];
        const double b[3] = {1 - h.u - h.v, h.u, h.v};
        Vec3 m = (dm.V[tri[1]] - dm.V[tri[0]]).cross(dm.V[tri[2]] - dm.V[tri[0]]);
        if (!(m.norm() > 0)) m = b[0] * base.normal[tri[0]] + b[1] * base.normal[tri[1]] + b[2] * base.normal[tri[2]];
        if (!(m.norm() > 0)) continue;
        m.normalize();
        // Point-to-plane row: the foot's displacement along m must close the gap to x.
        Vec3 L = Vec3::Zero();
        int len = 0;
        for (int c = 0; c < 3; ++c) {
          const int k = tri[c];
          L += b[c] * base.mesh.V[k];
          const double ck = b[c] * base.normal[k].dot(m);
          for (int q = 0; q < model.Terms(k); ++q) {
            rowIdx[r][len] = model.Unknowns(k)[q];
            rowW[r][len] = ck * model.Weights(k)[q];
            ++len;
          }
        }
        rowLen[r] = len;
        rhs0[r] = (x - L).dot(m);
      }
    }
    double sum = 0;
    for (int r = 0; r < nR; ++r) sum += dist[r] * dist[r];
    const double rms = std::sqrt(sum / nR);
    if (it == 0) {
      st.rmsBefore = rms;
      st.fitted = true;  // evaluated: from here the stats are meaningful
    }
    if (!(rms < bestRms)) break;  // no improvement: keep the previous iterate
    bestRms = rms;
    best = d;
    st.iterations = it;
    if (it == p.iterations) break;
    // Normal equations (AᵀA + w_a I) d = Aᵀb + w_a d0.
    std::vector<Eigen::Triplet<double>> trip;
    size_t entries = size_t(nX);
    for (int r = 0; r < nR; ++r) entries += size_t(rowLen[r]) * rowLen[r];
    trip.reserve(entries);
    Eigen::VectorXd rhs = p.anchorWeight * d0;
    for (int r = 0; r < nR; ++r)
      for (int s1 = 0; s1 < rowLen[r]; ++s1) {
        rhs[rowIdx[r][s1]] += rowW[r][s1] * rhs0[r];
        for (int s2 = 0; s2 < rowLen[r]; ++s2)
          trip.emplace_back(rowIdx[r][s1], rowIdx[r][s2], rowW[r][s1] * rowW[r][s2]);
      }
    for (int x = 0; x < nX; ++x) trip.emplace_back(x, x, p.anchorWeight);
    Eigen::SparseMatrix<double> Nm(nX, nX);
    Nm.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(Nm);
    if (solver.info() != Eigen::Success) break;
    Eigen::VectorXd dn = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !dn.allFinite()) break;
    d = dn.cwiseMax(-maxDist).cwiseMin(maxDist);
  }
  st.rmsAfter = std::isfinite(bestRms) ? bestRms : st.rmsBefore;
  if (st.iterations > 0) {  // a solve was kept (else the atlas stays exactly as baked)
    model.Space().Scatter(best, a);
    Quantize(a);
  }
  return st;
}

int FoldedTriangles(const LimitTessellation& t) {
  int n = 0;
  for (const auto& f : t.mesh.F) {
    const Vec3 fn = (t.mesh.V[f[1]] - t.mesh.V[f[0]]).cross(t.mesh.V[f[2]] - t.mesh.V[f[0]]);
    if (fn.dot(t.normal[f[0]] + t.normal[f[1]] + t.normal[f[2]]) < 0) ++n;
  }
  return n;
}

LimitTessellation DisplacedSurface(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const DisplacementAtlas& a,
                                   int minSegments) {
  if (!LayoutOk(a, ls.NumFaces()) || a.q16.size() != a.disp.size()) return {};
  LimitTessellation t = TessellateLimit(ls, ctrl, DisplacedSegments(a, minSegments));
  for (size_t v = 0; v < t.mesh.V.size(); ++v) {
    const int f = t.face[v];
    const TileCell c = CellAt(t.uv[v], a.tileR[f] - 1);
    const int i = c.i, j = c.j;
    const double d = c.w[0] * a.Decoded(f, i, j) + c.w[1] * a.Decoded(f, i + 1, j) +
                     c.w[2] * a.Decoded(f, i, j + 1) + c.w[3] * a.Decoded(f, i + 1, j + 1);
    t.mesh.V[v] += d * t.normal[v];
  }
  return t;
}

std::pair<double, double> ReferenceToSurfaceError(const TriData& ref, const TriData& surf) {
  return ReferenceToSurfaceError(ref, EmbreeScene(surf));
}
std::pair<double, double> ReferenceToSurfaceError(const TriData& ref, const EmbreeScene& s) {
  if (!s.Ok() || ref.V.empty()) return {0.0, 0.0};
  double sum = 0, mx = 0;
#pragma omp parallel reduction(+ : sum) reduction(max : mx)
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long i = 0; i < long(ref.V.size()); ++i) {
      EmbreeScene::Hit h = s.ClosestPoint(ref.V[i], std::numeric_limits<double>::infinity(), hint);
      if (h.valid) hint = h.face;
      double d = h.valid ? (h.point - ref.V[i]).norm() : 0.0;
      sum += d * d;
      mx = std::max(mx, d);
    }
  }
  return {std::sqrt(sum / ref.V.size()), mx};
}

std::pair<double, double> AreaSampledDistance(const TriData& from, const TriData& to, bool threePoint) {
  return AreaSampledDistance(from, EmbreeScene(to), threePoint);
}
std::pair<double, double> AreaSampledDistance(const TriData& from, const EmbreeScene& s, bool threePoint) {
  if (!s.Ok() || from.F.empty()) return {0.0, 0.0};
  double sw = 0, sd = 0, mx = 0;
#pragma omp parallel reduction(+ : sw, sd) reduction(max : mx)
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long t = 0; t < long(from.F.size()); ++t) {
      const auto& f = from.F[t];
      const Vec3 &a = from.V[f[0]], &b = from.V[f[1]], &c = from.V[f[2]];
      const double w = 0.5 * (b - a).cross(c - a).norm() / (threePoint ? 3 : 1);
      for (int k = 0; k < (threePoint ? 3 : 1); ++k) {
        const Vec3 q = threePoint ? Vec3((a + b + c + 3.0 * (k == 0 ? a : k == 1 ? b : c)) / 6.0) : Vec3((a + b + c) / 3.0);
        const EmbreeScene::Hit h = s.ClosestPoint(q, std::numeric_limits<double>::infinity(), hint);
        if (h.valid) hint = h.face;
        const double d = h.valid ? (h.point - q).norm() : 0.0;
        sw += w;
        sd += w * d * d;
        mx = std::max(mx, d);
      }
    }
  }
  return {sw > 0 ? std::sqrt(sd / sw) : 0.0, mx};
}

double UnprojectablePercent(const LimitTessellation& lim, const TriData& ref, const EmbreeScene& scene, double maxDist) {
  return UnprojectablePercent(lim, EmbreeScene(lim.mesh), ref, scene, maxDist);
}
double UnprojectablePercent(const LimitTessellation& lim, const EmbreeScene& ls, const TriData& ref,
                            const EmbreeScene& scene, double maxDist) {
  const int nT = int(ref.F.size());
  if (nT == 0) return 0.0;
  std::vector<unsigned char> reached(nT, 0);
#pragma omp parallel for schedule(static)
  for (long v = 0; v < long(lim.mesh.V.size()); ++v) {
    if (lim.normal[v].squaredNorm() == 0) continue;
    EmbreeScene::Hit h = scene.IntersectLine(lim.mesh.V[v], lim.normal[v], maxDist);
    if (h.valid) {
#pragma omp atomic write
      reached[h.face] = 1;
    }
  }
  double total = 0, missed = 0;
#pragma omp parallel reduction(+ : total, missed)
  {
    int hint = -1;
#pragma omp for schedule(dynamic, 64)
    for (int t = 0; t < nT; ++t) {
      const auto& f = ref.F[t];
      const Vec3 &a = ref.V[f[0]], &b = ref.V[f[1]], &c = ref.V[f[2]];
      const double area = 0.5 * (b - a).cross(c - a).norm();
      total += area;
      unsigned char r;
#pragma omp atomic read
      r = reached[t];
      if (r) continue;
      bool ok = false;
      EmbreeScene::Hit q = ls.ClosestPoint((a + b + c) / 3.0, maxDist, hint);
      if (q.valid) {
        hint = q.face;
        const auto& g = lim.mesh.F[q.face];
        Vec3 n = (1 - q.u - q.v) * lim.normal[g[0]] + q.u * lim.normal[g[1]] + q.v * lim.normal[g[2]];
        if (n.norm() > 0) {
          EmbreeScene::Hit h = scene.IntersectLine(q.point, n.normalized(), maxDist);
          ok = h.valid && h.face == t;
        }
      }
      if (!ok) missed += area;
    }
  }
  return total > 0 ? 100.0 * missed / total : 0.0;
}

FitBakeResult FitAndBake(const QuadData& control, const TriData& ref, const EmbreeScene& scene, const FitBakeParams& p,
                         vcg::CallBackPos* cb) {
  FitBakeResult r;
  const auto t0 = Clock::now();
  Progress prog(cb);
  r.referenceVertices = int(ref.V.size());
  r.referenceFaces = int(ref.F.size());
  if (p.limitSegments < 1 || p.textureResolution < 0 || p.textureResolution == 1 || p.maxDistPercent <= 0 ||
      p.metricSegments < 0 || p.maxTexels < 0) {
    r.error = "invalid parameters (limit segments >= 1, texture resolution 0 (auto) or >= 2, positive distance)";
    return r;
  }
  r.fit = FitCatmullClark(control, ref, scene, p.fit, nullptr);
  if (!r.fit.error.empty()) { r.error = r.fit.error; return r; }
  r.times.emplace_back("fit", r.fit.seconds);
  r.memory.emplace_back("fit", StagePeakMemoryMb());
  prog(50, "Fit and bake: tessellating", true);
  const double diag = BBoxDiagonal(ref.V);
  const double maxDist = p.maxDistPercent / 100.0 * diag;
  auto t = Clock::now();
  LimitSurface ls = LimitSurface::FromQuads(r.fit.control);
  if (!ls.Ok()) { r.error = ls.Error(); return r; }
  const auto& ctrl = r.fit.control.V;
  r.limit = TessellateLimit(ls, ctrl, p.limitSegments);
  r.limit.quality = SignedDistanceToReference(r.limit.mesh.V, scene, std::numeric_limits<double>::infinity());
  r.times.emplace_back("tessellate", Since(t));
  r.memory.emplace_back("tessellate", StagePeakMemoryMb());
  prog(60, "Fit and bake: baking displacement", true);
  t = Clock::now();
  // the paper's budget, one texel per reference vertex, up to the cap
  const int budgetVertices = p.maxTexels > 0 ? std::min(r.referenceVertices, p.maxTexels) : r.referenceVertices;
  if (p.textureResolution > 0 || !p.adaptiveTiles)
    UniformAtlasLayout(r.atlas, ls.NumFaces(),
                       p.textureResolution > 0 ? p.textureResolution
                                               : AutoTextureResolution(budgetVertices, ls.NumFaces()));
  else
    AdaptiveAtlasLayout(r.atlas, AdaptiveTileResolutions(PatchAreas(r.limit, ls.NumFaces()),
                                                         PatchVertexCounts(r.limit, ls.NumFaces(), ref),
                                                         AutoTextureBudget(budgetVertices, ls.NumFaces())));
  BakeDisplacement(ls, ctrl, ref, scene, maxDist, p.normalMap, r.atlas);
  if (p.fitDisplacement)
    r.displacementFit = FitDisplacement(ls, ctrl, ref, p.limitSegments, maxDist, p.displacementFit, r.atlas);
  r.displaced = DisplacedSurface(ls, ctrl, r.atlas, p.limitSegments);
  r.displaced.quality = SignedDistanceToReference(r.displaced.mesh.V, scene, std::numeric_limits<double>::infinity());
  r.times.emplace_back("bake", Since(t));
  r.memory.emplace_back("bake", StagePeakMemoryMb());
  if (p.computeMetrics) {
    prog(75, "Fit and bake: measuring", true);
    t = Clock::now();
    int Nm = p.metricSegments;
    if (Nm == 0)
      Nm = std::max(p.limitSegments,
                    int(std::ceil(std::sqrt(2.0 * double(ref.F.size()) / std::max(ls.NumFaces(), 1)))));
    LimitTessellation dense = Nm == p.limitSegments ? r.limit : TessellateLimit(ls, ctrl, Nm);
    const EmbreeScene denseScene(dense.mesh);  // one scene for the limit error and projectability
    auto el = ReferenceToSurfaceError(ref, denseScene);
    const EmbreeScene displacedScene(r.displaced.mesh);  // one scene for both displaced checks
    auto ed = ReferenceToSurfaceError(ref, displacedScene);
    const double pm = diag > 0 ? 1000.0 / diag : 0.0;
    r.metrics.rmsLimitPermille = el.first * pm;
    r.metrics.maxLimitPermille = el.second * pm;
    r.metrics.rmsDisplacedPermille = ed.first * pm;
    r.metrics.maxDisplacedPermille = ed.second * pm;
    double mx = 0;
    for (double q : r.limit.quality) mx = std::max(mx, std::abs(q));
    r.metrics.maxLimitToRefPermille = mx * pm;
    r.metrics.rmsDisplacedAreaPermille = AreaSampledDistance(ref, displacedScene).first * pm;
    const auto dr = AreaSampledDistance(r.displaced.mesh, scene, true);  // `scene` is the reference's
    r.metrics.rmsDisplacedToRefPermille = dr.first * pm;
    r.metrics.maxDisplacedToRefPermille = dr.second * pm;
    r.metrics.displacedFolds = FoldedTriangles(r.displaced);
    r.metrics.limitFolds = FoldedTriangles(dense);
    r.metrics.unprojectablePct = UnprojectablePercent(dense, denseScene, ref, scene, maxDist);
    r.times.emplace_back("metrics", Since(t));
    r.memory.emplace_back("metrics", StagePeakMemoryMb());
  }
  r.totalSeconds = Since(t0);
  // Set-up between the timed stages (limit surface, scenes): its own entry, so that the stages
  // add up to the total exactly (the report promises that).
  double staged = 0;
  for (const auto& st : r.times) staged += st.second;
  r.times.emplace_back("fit_setup", std::max(0.0, r.totalSeconds - staged));
  r.totalSeconds = staged + r.times.back().second;
  r.peakMemoryMb = ProcessPeakMemoryMb();
  r.warnings = ResultWarnings(r);
  prog(100, "Fit and bake: done", true);
  return r;
}

std::vector<std::string> ResultWarnings(const FitBakeResult& r) {
  std::vector<std::string> w;
  char buf[400];
  if (r.metrics.unprojectablePct > 1.0) {
    std::snprintf(buf, sizeof buf,
                  "%.2f %% of the reference area is not reached by projection from the limit surface (more than 1 %%): "
                  "the displacement does not cover it; use a smaller tau or more patches",
                  r.metrics.unprojectablePct);
    w.push_back(buf);
  }
  if (r.metrics.maxLimitPermille > 20.0) {
    std::snprintf(buf, sizeof buf,
                  "the smooth limit surface stays up to %.1f permille of the bbox diagonal from the reference (RMS %.2f): "
                  "sharp corners or creases that a Catmull-Clark limit cannot follow with %d patches; the "
                  "displacement carries the rest (RMS %.3f permille)",
                  r.metrics.maxLimitPermille, r.metrics.rmsLimitPermille, r.fit.patches, r.metrics.rmsDisplacedPermille);
    w.push_back(buf);
  }
  return w;
}

std::string FormatReport(const FitBakeResult& r) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(3);
  if (!r.error.empty()) { o << "error: " << r.error << "\n"; return o.str(); }
  o << "patches " << r.fit.patches << ", irregular vertices " << r.fit.irregularVertices << ", degenerate patches "
    << r.fit.degeneratePatches << "\n";
  o << "samples " << r.fit.samples << " (k " << r.fit.minKUsed << ".." << r.fit.maxKUsed << "), iterations "
    << r.fit.iterations << ", ray misses " << 100 * r.fit.rayMissFraction << "%\n";
  o << "unprojectable " << r.metrics.unprojectablePct << "% of the reference area\n";
  o << "limit error RMS " << r.metrics.rmsLimitPermille << " max " << r.metrics.maxLimitPermille
    << " (permille of bbox diagonal, per reference vertex)\n";
  o << "displaced error RMS " << r.metrics.rmsDisplacedPermille << " max " << r.metrics.maxDisplacedPermille
    << " (texture " << r.atlas.width << "x" << r.atlas.height << ", "
    << (r.atlas.adaptive ? "adaptive tiles " : "tile ")
    << (r.atlas.tileR.empty() ? 0 : *std::min_element(r.atlas.tileR.begin(), r.atlas.tileR.end()))
    << (r.atlas.adaptive ? ".." + std::to_string(r.atlas.R) : std::string()) << ", " << r.atlas.Samples()
    << " samples, "
    << (r.displacementFit.fitted ? "least-squares texels" : "point-sampled texels") << ")\n";
  o << "displaced error area-weighted: reference -> displaced RMS " << r.metrics.rmsDisplacedAreaPermille
    << ", displaced -> reference RMS " << r.metrics.rmsDisplacedToRefPermille << " max "
    << r.metrics.maxDisplacedToRefPermille << " (permille)\n";
  o << "folded triangles (facing against the limit normal): displaced layer " << r.metrics.displacedFolds
    << ", limit tessellation " << r.metrics.limitFolds << "\n";
  o << "time:";
  for (const auto& t : r.times) o << " " << t.first << " " << t.second << " s,";
  o << " total " << r.totalSeconds << " s; peak memory " << r.peakMemoryMb << " MB\n";
  return o.str();
}

}  // namespace vcgext
