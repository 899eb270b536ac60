#include "vcg_ext/fit/bake.h"

#include <sys/resource.h>

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
  LimitTessellation t;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || N < 1 || nF == 0) return t;
  // Vertex ids: control corners shared, edge points shared per undirected edge, interiors own.
  std::vector<int> cornerId(ls.NumVertices(), -1);
  std::unordered_map<std::uint64_t, int> edgeBase;  // first id of the N-1 interior points of edge (a<b)
  t.N = N;
  std::vector<int>& gridId = t.grid;
  gridId.resize(size_t(nF) * (N + 1) * (N + 1));
  auto addVertex = [&](int f, double u, double v) {
    t.face.push_back(f);
    t.uv.emplace_back(u, v);
    return int(t.face.size()) - 1;
  };
  int cv[4];
  for (int f = 0; f < nF; ++f) {
    int* g = gridId.data() + size_t(f) * (N + 1) * (N + 1);
    // Corner control vertices: the corner (u,v) convention (0,0),(1,0),(1,1),(0,1).
    const int cu[4] = {0, N, N, 0}, cvv[4] = {0, 0, N, N};
    for (int c = 0; c < 4; ++c) cv[c] = ls.FaceVertex(f, c);
    for (int c = 0; c < 4; ++c) {
      int& id = cornerId[cv[c]];
      if (id < 0) id = addVertex(f, double(cu[c]) / N, double(cvv[c]) / N);
      g[cvv[c] * (N + 1) + cu[c]] = id;
    }
    // Edges: e0 c0->c1 (j=0, i=m), e1 c1->c2 (i=N, j=m), e2 c2->c3 (j=N, i=N-m), e3 c3->c0 (i=0, j=N-m).
    auto edgeGrid = [N](int e, int m, int* i, int* j) {
      switch (e) {
        case 0: *i = m; *j = 0; break;
        case 1: *i = N; *j = m; break;
        case 2: *i = N - m; *j = N; break;
        default: *i = 0; *j = N - m; break;
      }
    };
    for (int e = 0; e < 4; ++e) {
      int a = cv[e], b = cv[(e + 1) % 4];
      bool fwd = a < b;
      auto key = fwd ? EdgeKey(a, b) : EdgeKey(b, a);
      auto it = edgeBase.find(key);
      int base;
      bool created = false;
      if (it == edgeBase.end()) { base = int(t.face.size()); edgeBase.emplace(key, base); created = true; }
      else base = it->second;
      for (int m = 1; m < N; ++m) {
        int i, j;
        edgeGrid(e, m, &i, &j);
        int cm = fwd ? m : N - m;  // canonical position along a<b
        g[j * (N + 1) + i] = base + cm - 1;
      }
      if (created) {
        for (int cm = 1; cm < N; ++cm) {
          int i, j;
          edgeGrid(e, fwd ? cm : N - cm, &i, &j);
          addVertex(f, double(i) / N, double(j) / N);
        }
      }
    }
    for (int j = 1; j < N; ++j)
      for (int i = 1; i < N; ++i) g[j * (N + 1) + i] = addVertex(f, double(i) / N, double(j) / N);
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) {
        int v00 = g[j * (N + 1) + i], v10 = g[j * (N + 1) + i + 1];
        int v11 = g[(j + 1) * (N + 1) + i + 1], v01 = g[(j + 1) * (N + 1) + i];
        t.mesh.F.push_back({v00, v10, v11});
        t.mesh.F.push_back({v00, v11, v01});
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
#pragma omp parallel for schedule(static)
  for (long i = 0; i < long(pts.size()); ++i) {
    EmbreeScene::Hit h = ref.ClosestPoint(pts[i], maxDist);
    if (!h.valid) continue;
    Vec3 dv = pts[i] - h.point;
    double s = dv.dot(fn[h.face]) < 0 ? -1.0 : 1.0;
    d[i] = s * dv.norm();
  }
  return d;
}

int AutoTextureResolution(int referenceVertices, int patches) {
  if (patches <= 0) return kMinAutoTextureResolution;
  return std::max(kMinAutoTextureResolution, int(std::lround(std::sqrt(double(referenceVertices) / patches))));
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
void Quantize(DisplacementAtlas& a, int nF) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int f = 0; f < nF; ++f)
    for (int j = 0; j < a.R; ++j)
      for (int i = 0; i < a.R; ++i) {
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
}  // namespace

DisplacementAtlas BakeDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                   const EmbreeScene& scene, int R, double maxDist, bool normalMap) {
  DisplacementAtlas a;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || R < 2) return a;
  a.R = R;
  a.cols = int(std::ceil(std::sqrt(double(nF))));
  a.rows = (nF + a.cols - 1) / a.cols;
  a.width = a.cols * R;
  a.height = a.rows * R;
  a.disp.assign(size_t(a.width) * a.height, 0.f);
  if (normalMap) a.normalRGB.assign(size_t(a.width) * a.height * 3, 128);
  std::vector<Vec3> vn;
  if (normalMap) vn = VertexNormals(ref);
  const std::vector<Vec3> refN = FaceNormals(ref);
  int misses = 0;
#pragma omp parallel for schedule(dynamic, 8) reduction(+ : misses)
  for (int f = 0; f < nF; ++f) {
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
  Quantize(a, nF);
  // Wedge UVs at the corner texels' centres; v up (OpenGL / OBJ / MeshLab), image row 0 on top.
  a.wedgeUV.resize(nF);
  const int cu[4] = {0, 1, 1, 0}, cvv[4] = {0, 0, 1, 1};
  for (int f = 0; f < nF; ++f) {
    const int x0 = (f % a.cols) * R, y0 = (f / a.cols) * R;
    for (int c = 0; c < 4; ++c) {
      double x = x0 + 0.5 + cu[c] * (R - 1), y = y0 + 0.5 + cvv[c] * (R - 1);
      a.wedgeUV[f][c] = Eigen::Vector2d(x / a.width, 1.0 - y / a.height);
    }
  }
  return a;
}

namespace {
// The displaced layer as a linear function of the texels: its base tessellation (what
// DisplacedSurface displaces, max(R−1, minSegments) per side) and, per base vertex, the bilinear
// filter weights of the 4 texels of its tile. Texels are numbered on the welded grid of
// TessellateLimit(R−1): texels on shared tile edges/corners are one unknown (seamless tiles).
class DisplacedModel {
 public:
  DisplacedModel(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int R, int minSegments)
      : T_(R - 1), nF_(ls.NumFaces()) {
    base_ = TessellateLimit(ls, ctrl, std::max(T_, minSegments));
    if (base_.N != T_) texGrid_ = TessellateLimit(ls, ctrl, T_);
    const int nB = NumBase();
    bt_.resize(nB);
    bw_.resize(nB);
    for (int k = 0; k < nB; ++k) {
      const TileCell c = CellAt(base_.uv[k], T_);
      const int f = base_.face[k];
      bt_[k] = {Tex().GridId(f, c.i, c.j), Tex().GridId(f, c.i + 1, c.j), Tex().GridId(f, c.i, c.j + 1),
                Tex().GridId(f, c.i + 1, c.j + 1)};
      bw_[k] = {c.w[0], c.w[1], c.w[2], c.w[3]};
    }
  }
  const LimitTessellation& Base() const { return base_; }
  const LimitTessellation& Tex() const { return base_.N == T_ ? base_ : texGrid_; }
  int NumTexels() const { return int(Tex().mesh.V.size()); }
  int NumBase() const { return int(base_.mesh.V.size()); }
  const std::array<int, 4>& Texels(int k) const { return bt_[k]; }
  const std::array<double, 4>& Weights(int k) const { return bw_[k]; }
  // Texel values of the atlas's tiles, by welded id.
  Eigen::VectorXd Gather(const DisplacementAtlas& a) const {
    Eigen::VectorXd d(NumTexels());
    for (int f = 0; f < nF_; ++f)
      for (int j = 0; j <= T_; ++j)
        for (int i = 0; i <= T_; ++i) d[Tex().GridId(f, i, j)] = a.disp[a.Pixel(f, i, j)];
    return d;
  }
  // Writes the texel values into every tile (shared texels into each tile that has them).
  void Scatter(const Eigen::VectorXd& d, DisplacementAtlas& a) const {
    for (int f = 0; f < nF_; ++f)
      for (int j = 0; j <= T_; ++j)
        for (int i = 0; i <= T_; ++i) a.disp[a.Pixel(f, i, j)] = float(d[Tex().GridId(f, i, j)]);
  }
  double Displacement(int k, const Eigen::VectorXd& d) const {
    double s = 0;
    for (int q = 0; q < 4; ++q) s += bw_[k][q] * d[bt_[k][q]];
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
  int T_, nF_;
  LimitTessellation base_, texGrid_;
  std::vector<std::array<int, 4>> bt_;
  std::vector<std::array<double, 4>> bw_;
};
}  // namespace

DisplacementFitStats FitDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                     int minSegments, double maxDist, const DisplacementFitParams& p,
                                     DisplacementAtlas& a) {
  DisplacementFitStats st;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || a.R < 2 || ref.V.empty() || p.iterations < 1 || !(p.anchorWeight > 0) ||
      !(maxDist > 0))
    return st;
  // the atlas must be a layout of this surface (BakeDisplacement's)
  if (a.cols < 1 || a.rows < 1 || size_t(a.cols) * a.rows < size_t(nF) || a.width != a.cols * a.R ||
      a.height != a.rows * a.R || a.disp.size() != size_t(a.width) * a.height)
    return st;
  const DisplacedModel model(ls, ctrl, a.R, minSegments);
  const LimitTessellation& base = model.Base();
  const int nX = model.NumTexels();
  // Point-sampled (ray) values: the anchor of every texel.
  const Eigen::VectorXd d0 = model.Gather(a);
  Eigen::VectorXd d = d0;
  const int nR = int(ref.V.size());
  constexpr int kMaxRow = 12;  // 3 triangle corners × 4 bilinear texels
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
#pragma omp parallel for schedule(static)
    for (int r = 0; r < nR; ++r) {
      const Vec3& x = ref.V[r];
      const EmbreeScene::Hit h = scene.ClosestPoint(x);
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
        for (int q = 0; q < 4; ++q)
          if (model.Weights(k)[q] != 0) {
            rowIdx[r][len] = model.Texels(k)[q];
            rowW[r][len] = ck * model.Weights(k)[q];
            ++len;
          }
      }
      rowLen[r] = len;
      rhs0[r] = (x - L).dot(m);
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
    model.Scatter(best, a);
    Quantize(a, nF);
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
  const int T = a.R - 1;  // texel intervals per tile side
  LimitTessellation t = TessellateLimit(ls, ctrl, std::max(T, minSegments));
  for (size_t v = 0; v < t.mesh.V.size(); ++v) {
    const TileCell c = CellAt(t.uv[v], T);
    const int f = t.face[v], i = c.i, j = c.j;
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
#pragma omp parallel for schedule(static) reduction(+ : sum) reduction(max : mx)
  for (long i = 0; i < long(ref.V.size()); ++i) {
    EmbreeScene::Hit h = s.ClosestPoint(ref.V[i]);
    double d = h.valid ? (h.point - ref.V[i]).norm() : 0.0;
    sum += d * d;
    mx = std::max(mx, d);
  }
  return {std::sqrt(sum / ref.V.size()), mx};
}

std::pair<double, double> AreaSampledDistance(const TriData& from, const TriData& to, bool threePoint) {
  return AreaSampledDistance(from, EmbreeScene(to), threePoint);
}
std::pair<double, double> AreaSampledDistance(const TriData& from, const EmbreeScene& s, bool threePoint) {
  if (!s.Ok() || from.F.empty()) return {0.0, 0.0};
  double sw = 0, sd = 0, mx = 0;
#pragma omp parallel for schedule(static) reduction(+ : sw, sd) reduction(max : mx)
  for (long t = 0; t < long(from.F.size()); ++t) {
    const auto& f = from.F[t];
    const Vec3 &a = from.V[f[0]], &b = from.V[f[1]], &c = from.V[f[2]];
    const double w = 0.5 * (b - a).cross(c - a).norm() / (threePoint ? 3 : 1);
    for (int k = 0; k < (threePoint ? 3 : 1); ++k) {
      const Vec3 q = threePoint ? Vec3((a + b + c + 3.0 * (k == 0 ? a : k == 1 ? b : c)) / 6.0) : Vec3((a + b + c) / 3.0);
      const EmbreeScene::Hit h = s.ClosestPoint(q);
      const double d = h.valid ? (h.point - q).norm() : 0.0;
      sw += w;
      sd += w * d * d;
      mx = std::max(mx, d);
    }
  }
  return {sw > 0 ? std::sqrt(sd / sw) : 0.0, mx};
}

double UnprojectablePercent(const LimitTessellation& lim, const TriData& ref, const EmbreeScene& scene, double maxDist) {
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
  EmbreeScene ls(lim.mesh);
  double total = 0, missed = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : total, missed)
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
    EmbreeScene::Hit q = ls.ClosestPoint((a + b + c) / 3.0, maxDist);
    if (q.valid) {
      const auto& g = lim.mesh.F[q.face];
      Vec3 n = (1 - q.u - q.v) * lim.normal[g[0]] + q.u * lim.normal[g[1]] + q.v * lim.normal[g[2]];
      if (n.norm() > 0) {
        EmbreeScene::Hit h = scene.IntersectLine(q.point, n.normalized(), maxDist);
        ok = h.valid && h.face == t;
      }
    }
    if (!ok) missed += area;
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
      p.metricSegments < 0) {
    r.error = "invalid parameters (limit segments >= 1, texture resolution 0 (auto) or >= 2, positive distance)";
    return r;
  }
  r.fit = FitCatmullClark(control, ref, scene, p.fit, nullptr);
  if (!r.fit.error.empty()) { r.error = r.fit.error; return r; }
  r.times.emplace_back("fit", r.fit.seconds);
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
  prog(60, "Fit and bake: baking displacement", true);
  t = Clock::now();
  const int R = p.textureResolution > 0 ? p.textureResolution : AutoTextureResolution(r.referenceVertices, ls.NumFaces());
  r.atlas = BakeDisplacement(ls, ctrl, ref, scene, R, maxDist, p.normalMap);
  if (p.fitDisplacement)
    r.displacementFit = FitDisplacement(ls, ctrl, ref, p.limitSegments, maxDist, p.displacementFit, r.atlas);
  r.displaced = DisplacedSurface(ls, ctrl, r.atlas, p.limitSegments);
  r.displaced.quality = SignedDistanceToReference(r.displaced.mesh.V, scene, std::numeric_limits<double>::infinity());
  r.times.emplace_back("bake", Since(t));
  if (p.computeMetrics) {
    prog(75, "Fit and bake: measuring", true);
    t = Clock::now();
    int Nm = p.metricSegments;
    if (Nm == 0)
      Nm = std::max(p.limitSegments,
                    int(std::ceil(std::sqrt(2.0 * double(ref.F.size()) / std::max(ls.NumFaces(), 1)))));
    LimitTessellation dense = Nm == p.limitSegments ? r.limit : TessellateLimit(ls, ctrl, Nm);
    auto el = ReferenceToSurfaceError(ref, dense.mesh);
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
    r.metrics.unprojectablePct = UnprojectablePercent(dense, ref, scene, maxDist);
    r.times.emplace_back("metrics", Since(t));
  }
  r.totalSeconds = Since(t0);
  // Set-up between the timed stages (limit surface, scenes): its own entry, so that the stages
  // add up to the total exactly (the report promises that).
  double staged = 0;
  for (const auto& st : r.times) staged += st.second;
  r.times.emplace_back("fit_setup", std::max(0.0, r.totalSeconds - staged));
  r.totalSeconds = staged + r.times.back().second;
  struct rusage ru;
  if (getrusage(RUSAGE_SELF, &ru) == 0) r.peakMemoryMb = ru.ru_maxrss / 1024.0;
  prog(100, "Fit and bake: done", true);
  return r;
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
    << " (texture " << r.atlas.width << "x" << r.atlas.height << ", tile " << r.atlas.R << ", "
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
