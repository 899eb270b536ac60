#include "vcg_ext/fitmaps/fitmaps_internal.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace vcgext {
namespace fitmaps_internal {

Frame Frame::Make(const Vec3& origin, const Vec3& unitNormal) {
  Frame f;
  f.o = origin;
  f.n = unitNormal;
  // Tangent u: the coordinate axis least aligned with n, orthogonalised (stable for any n).
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(unitNormal[i]) < std::abs(unitNormal[k])) k = i;
  Vec3 a = Vec3::Zero();
  a[k] = 1;
  f.u = (a - a.dot(f.n) * f.n).normalized();
  f.v = f.n.cross(f.u);
  return f;
}

double Cubic::Eval(double u, double v) const {
  const double s = u / r, t = v / r;
  return c[0] + s * (c[1] + s * (c[3] + s * c[6]) + t * (c[4] + s * c[7])) +
         t * (c[2] + t * (c[5] + t * c[9] + s * c[8]));
}

void Cubic::Eval2(double u, double v, double& h, double& hu, double& hv, double& huu, double& huv,
                  double& hvv) const {
  const double s = u / r, t = v / r, ir = 1.0 / r;
  h = Eval(u, v);
  hu = (c[1] + 2 * c[3] * s + c[4] * t + 3 * c[6] * s * s + 2 * c[7] * s * t + c[8] * t * t) * ir;
  hv = (c[2] + c[4] * s + 2 * c[5] * t + c[7] * s * s + 2 * c[8] * s * t + 3 * c[9] * t * t) * ir;
  huu = (2 * c[3] + 6 * c[6] * s + 2 * c[7] * t) * ir * ir;
  huv = (c[4] + 2 * c[7] * s + 2 * c[8] * t) * ir * ir;
  hvv = (2 * c[5] + 2 * c[8] * s + 6 * c[9] * t) * ir * ir;
}

Vec3 Cubic::Normal(double u, double v) const {
  double h, hu, hv, a, b, c2;
  Eval2(u, v, h, hu, hv, a, b, c2);
  return Vec3(-hu, -hv, 1.0).normalized();
}

namespace {
constexpr int kDeg[10] = {0, 1, 1, 2, 2, 2, 3, 3, 3, 3};
inline void Monomials(double s, double t, double* m) {
  m[0] = 1; m[1] = s; m[2] = t;
  m[3] = s * s; m[4] = s * t; m[5] = t * t;
  m[6] = m[3] * s; m[7] = m[3] * t; m[8] = s * m[5]; m[9] = t * m[5];
}
}  // namespace

void CubicAccumulator::Add(double u, double v, double h, double w) {
  double m[10];
  Monomials(u, v, m);
  for (int j = 0; j < 10; ++j) {
    const double wm = w * m[j];
    for (int i = j; i < 10; ++i) A_(i, j) += wm * m[i];
    b_[j] += wm * h;
  }
  ++n_;
}

bool CubicAccumulator::Solve(double r, Cubic& out) const {
  if (n_ == 0) return false;
  // Scale to (u,v)/r: A_s = D A D, b_s = D b with D = diag(r^-deg).
  double d[10];
  for (int k = 0; k < 10; ++k) d[k] = std::pow(r, -kDeg[k]);
  Eigen::Matrix<double, 10, 10> As;
  Eigen::Matrix<double, 10, 1> bs;
  for (int j = 0; j < 10; ++j) {
    for (int i = j; i < 10; ++i) As(i, j) = As(j, i) = A_(i, j) * d[i] * d[j];
    bs[j] = b_[j] * d[j];
  }
  const double ridge = 1e-10 * std::max(As.trace() / 10.0, 1e-300);
  As.diagonal().array() += ridge;
  Eigen::LDLT<Eigen::Matrix<double, 10, 10>> ldlt(As);
  Eigen::Matrix<double, 10, 1> c = ldlt.solve(bs);
  out.r = r;
  for (int k = 0; k < 10; ++k) out.c[k] = std::isfinite(c[k]) ? c[k] : 0.0;
  return true;
}

bool ClosestPointOnCubic(const Cubic& g, const Vec3& x, double maxUV, double& u, double& v) {
  u = x[0];
  v = x[1];
  const double tol = 1e-10 * g.r;
  for (int it = 0; it < 12; ++it) {
    double h, hu, hv, huu, huv, hvv;
    g.Eval2(u, v, h, hu, hv, huu, huv, hvv);
    const double dz = h - x[2];
    const double gu = (u - x[0]) + dz * hu, gv = (v - x[1]) + dz * hv;
    double a = 1 + hu * hu + dz * huu, b = hu * hv + dz * huv, c = 1 + hv * hv + dz * hvv;
    double det = a * c - b * b;
    if (!(a > 0 && det > 1e-12 * a * c)) {  // not convex here: Gauss-Newton (always SPD)
      a = 1 + hu * hu;
      b = hu * hv;
      c = 1 + hv * hv;
      det = a * c - b * b;
    }
    const double du = -(c * gu - b * gv) / det, dv = -(a * gv - b * gu) / det;
    u += du;
    v += dv;
    if (!std::isfinite(u) || !std::isfinite(v) || u * u + v * v > maxUV * maxUV) return false;
    if (std::abs(du) + std::abs(dv) < tol) return true;
  }
  return false;
}

void GatherScratch::Reset(size_t n) {
  if (key.size() != n) {
    key.assign(n, std::numeric_limits<double>::infinity());
    touched.clear();
    return;
  }
  for (int i : touched) key[i] = std::numeric_limits<double>::infinity();
  touched.clear();
}

void GatherMinimax(const Adjacency& adj, const std::vector<Vec3>& X, int src, double maxR,
                   GatherScratch& s, std::vector<std::pair<int, double>>& out, size_t maxCount,
                   const Vec3* center) {
  // Keys are kept squared (monotone, no square roots in the traversal).
  s.Reset(X.size());
  out.clear();
  s.heap.clear();
  const Vec3 p = center ? *center : X[src];
  const double maxR2 = maxR * maxR;
  const double k0 = (X[src] - p).squaredNorm();
  s.key[src] = k0;
  s.touched.push_back(src);
  s.heap.emplace_back(k0, src);
  auto cmp = std::greater<std::pair<double, int>>();
  while (!s.heap.empty()) {
    std::pop_heap(s.heap.begin(), s.heap.end(), cmp);
    auto [k, q] = s.heap.back();
    s.heap.pop_back();
    if (k > s.key[q]) continue;  // stale entry
    out.emplace_back(q, k);
    if (out.size() >= maxCount) break;
    for (const int* it = adj.Begin(q); it != adj.End(q); ++it) {
      const int nb = *it;
      double& kn = s.key[nb];
      if (kn <= k) continue;  // already final or as good
      const double d2 = (X[nb] - p).squaredNorm();
      if (d2 > maxR2) continue;
      const double nk = std::max(k, d2);
      if (nk < kn) {
        if (kn == std::numeric_limits<double>::infinity()) s.touched.push_back(nb);
        kn = nk;
        s.heap.emplace_back(nk, nb);
        std::push_heap(s.heap.begin(), s.heap.end(), cmp);
      }
    }
  }
  for (auto& o : out) o.second = std::sqrt(o.second);
  for (int i : s.touched) s.key[i] = std::sqrt(s.key[i]);
}

void GatherBall(const Adjacency& adj, const std::vector<Vec3>& X, int src, double r, GatherScratch& s,
                std::vector<std::pair<int, double>>& out, const Vec3* center) {
  s.Reset(X.size());
  out.clear();
  const Vec3 p = center ? *center : X[src];
  const double r2 = r * r;
  const double d0 = (X[src] - p).squaredNorm();
  if (d0 > r2) return;
  s.key[src] = d0;
  s.touched.push_back(src);
  out.emplace_back(src, d0);
  for (size_t head = 0; head < out.size(); ++head) {
    const int q = out[head].first;
    for (const int* it = adj.Begin(q); it != adj.End(q); ++it) {
      const int nb = *it;
      if (s.key[nb] != std::numeric_limits<double>::infinity()) continue;
      const double d2 = (X[nb] - p).squaredNorm();
      if (d2 > r2) continue;
      s.key[nb] = d2;
      s.touched.push_back(nb);
      out.emplace_back(nb, d2);
    }
  }
  for (auto& o : out) o.second = std::sqrt(o.second);
  for (int i : s.touched) s.key[i] = std::sqrt(s.key[i]);
}

Rng::Rng(uint64_t seed, uint64_t a, uint64_t b) {
  state = seed * 0x9E3779B97F4A7C15ull ^ (a + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull ^
          (b + 0x2545F4914F6CDD1Dull) * 0x94D049BB133111EBull;
  Next();
}

uint64_t Rng::Next() {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace fitmaps_internal
}  // namespace vcgext
