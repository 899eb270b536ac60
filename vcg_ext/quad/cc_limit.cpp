#include "vcg_ext/quad/cc_limit.h"

#include <Eigen/Sparse>
#include <Eigen/IterativeLinearSolvers>

#include <algorithm>
#include <cmath>

namespace vcgext {
namespace quad {

namespace {
thread_local std::vector<Wedge> tlFan;

// cos / sin of 2*pi*i/n for i = 0..n and the constants of the tangent masks, per valence n <
// kMaxTab (the same expressions as computed inline, so the values are bit-identical)
constexpr int kMaxTab = 33;
double FillTangents(int n, std::vector<double>& c, std::vector<double>& s) {
  const double nn = double(n);
  c.clear();
  s.clear();
  for (int i = 0; i <= n; ++i) {
    c.push_back(std::cos(2 * M_PI * i / nn));
    s.push_back(std::sin(2 * M_PI * i / nn));
  }
  const double c2 = std::cos(2 * M_PI / nn);
  return 1.0 + c2 + std::cos(M_PI / nn) * std::sqrt(2.0 * (9.0 + c2));  // A of the tangent masks
}
struct TangentTable {
  std::vector<double> c[kMaxTab], s[kMaxTab];
  double A[kMaxTab] = {};
  TangentTable() {
    for (int n = 1; n < kMaxTab; ++n) A[n] = FillTangents(n, c[n], s[n]);
  }
};
const TangentTable& Tangents() {
  static const TangentTable t;
  return t;
}
}

bool VertexLimitMask(const QuadMesh& m, int v, std::vector<std::pair<int, double>>& mask) {
  mask.clear();
  if (!m.VertAlive(v)) return false;
  std::vector<Wedge>& w = tlFan;
  bool open = false;
  if (!m.Fan(v, w, &open)) return false;
  if (open) {
    mask.push_back({v, 4.0 / 6.0});
    mask.push_back({w.front().p, 1.0 / 6.0});
    mask.push_back({w.back().n, 1.0 / 6.0});
    return true;
  }
  const double n = double(w.size());
  const double den = n * (n + 5.0);
  mask.push_back({v, n * n / den});
  for (const Wedge& x : w) {
    mask.push_back({x.n, 4.0 / den});
    mask.push_back({x.o, 1.0 / den});
  }
  return true;
}

Vec3 VertexLimit(const QuadMesh& m, int v) {
  thread_local std::vector<std::pair<int, double>> mask;
  if (!VertexLimitMask(m, v, mask)) return m.P[v];
  Vec3 p = Vec3::Zero();
  for (auto& [i, wt] : mask) p += wt * m.P[i];
  return p;
}

bool VertexLimitFrame(const QuadMesh& m, int v, Vec3* pos, Vec3* normal) {
  if (!m.VertAlive(v) || m.IsBoundary(v)) return false;
  std::vector<Wedge>& w = tlFan;
  bool open = false;
  if (!m.Fan(v, w, &open) || open) return false;
  const int n = int(w.size());
  const double nn = double(n);
  Vec3 p = nn * nn * m.P[v];
  for (const Wedge& x : w) p += 4.0 * m.P[x.n] + m.P[x.o];
  p /= nn * (nn + 5.0);
  if (pos) *pos = p;
  // e_i = w[i].n, f_i (between e_i and e_{i+1}) = w[i+1].o; the walk is clockwise.
  thread_local std::vector<double> bigC, bigS;  // valences beyond the table (never in practice)
  const double* cs;
  const double* sn;
  double A;
  if (n < kMaxTab) {
    const TangentTable& tab = Tangents();
    A = tab.A[n];
    cs = tab.c[n].data();
    sn = tab.s[n].data();
  } else {
    A = FillTangents(n, bigC, bigS);
    cs = bigC.data();
    sn = bigS.data();
  }
  Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    const Vec3& e = m.P[w[i].n];
    const Vec3& f = m.P[w[(i + 1) % n].o];
    t1 += A * cs[i] * e + (cs[i] + cs[i + 1]) * f;
    t2 += A * sn[i] * e + (sn[i] + sn[i + 1]) * f;
  }
  Vec3 nr = t2.cross(t1);  // clockwise walk: t2 x t1 follows the faces' orientation
  double l = nr.norm();
  if (!(l > 0)) return false;
  if (normal) *normal = nr / l;
  return true;
}

// ---------------------------------------------------------------------------- QuadMemo
void QuadMemo::Reset() {
  const size_t nf = m_->F.size();
  if (cStamp_.size() != nf) {
    cStamp_.assign(nf, 0);
    aStamp_.assign(nf, 0);
    cent_.resize(nf);
    adj_.resize(nf);
  }
  if (++epoch_ == 0) {  // wrapped: clear the stamps
    std::fill(cStamp_.begin(), cStamp_.end(), 0u);
    std::fill(aStamp_.begin(), aStamp_.end(), 0u);
    epoch_ = 1;
  }
}
const Vec3& QuadMemo::Centroid(int f) const {
  if (cStamp_[f] != epoch_) { cStamp_[f] = epoch_; cent_[f] = m_->Centroid(f); }
  return cent_[f];
}
void QuadMemo::Adjacency(int f) const {
  if (aStamp_[f] == epoch_) return;
  aStamp_[f] = epoch_;
  for (int k = 0; k < 4; ++k) adj_[f][k] = m_->AcrossEdge(f, k);
}
int QuadMemo::AcrossEdge(int f, int k) const {
  Adjacency(f);
  return adj_[f][k];
}
int QuadMemo::CountStale() const {
  int stale = 0;
  for (size_t f = 0; f < cStamp_.size(); ++f) {
    if (!m_->FaceAlive(int(f))) {
      stale += (cStamp_[f] == epoch_ || aStamp_[f] == epoch_) ? 1 : 0;
      continue;
    }
    if (cStamp_[f] == epoch_ && !(cent_[f] == m_->Centroid(int(f)))) ++stale;
    if (aStamp_[f] == epoch_)
      for (int k = 0; k < 4; ++k) stale += adj_[f][k] != m_->AcrossEdge(int(f), k) ? 1 : 0;
  }
  return stale;
}

// ---------------------------------------------------------------------------- stencils
// The stencils below are written once for any "view" (QuadMesh itself, or a QuadMemo) that
// provides Mesh(), Centroid(f) and AcrossEdge(f, k).
namespace {

template <class View>
Vec3 VertexPointT(const View& view, int v) {
  const QuadMesh& m = view.Mesh();
  std::vector<Wedge>& w = tlFan;
  bool open = false;
  if (!m.Fan(v, w, &open)) return m.P[v];
  if (open) return (m.P[w.front().p] + 6.0 * m.P[v] + m.P[w.back().n]) / 8.0;
  const double n = double(w.size());
  Vec3 Q = Vec3::Zero(), R = Vec3::Zero();
  for (const Wedge& x : w) {
    Q += view.Centroid(x.f);
    R += 0.5 * (m.P[v] + m.P[x.n]);
  }
  Q /= n;
  R /= n;
  return (Q + 2.0 * R + (n - 3.0) * m.P[v]) / n;
}

template <class View>
bool FaceCentreLimitT(const View& view, int f, const Vec3 V[4], Vec3* pos, Vec3* normal) {
  const QuadMesh& m = view.Mesh();
  if (!m.FaceAlive(f)) return false;
  const Quad& q = m.F[f];
  const Vec3 Fp = view.Centroid(f);
  Vec3 E[4];
  for (int k = 0; k < 4; ++k) {
    const Vec3& a = m.P[q[k]];
    const Vec3& b = m.P[q[(k + 1) & 3]];
    int g = view.AcrossEdge(f, k);
    E[k] = g < 0 ? Vec3(0.5 * (a + b)) : Vec3(0.25 * (a + b + Fp + view.Centroid(g)));
  }
  if (pos) *pos = (16.0 * Fp + 4.0 * (E[0] + E[1] + E[2] + E[3]) + (V[0] + V[1] + V[2] + V[3])) / 36.0;
  if (normal) {
    // regular bicubic B-spline at the centre of the 3x3 refined control grid:
    // u runs q0->q1 (E1 at u+, E3 at u-), v runs q0->q3 (E2 at v+, E0 at v-).
    Vec3 du = 4.0 * (E[1] - E[3]) + (V[1] + V[2] - V[0] - V[3]);
    Vec3 dv = 4.0 * (E[2] - E[0]) + (V[2] + V[3] - V[0] - V[1]);
    Vec3 nr = du.cross(dv);
    double l = nr.norm();
    if (!(l > 0)) return false;
    *normal = nr / l;
  }
  return true;
}

template <class View>
bool EdgeMidLimitT(const View& view, int f, int k, const Vec3* vp, Vec3* pos, Vec3* normal, bool* hasNormal) {
  const QuadMesh& m = view.Mesh();
  if (hasNormal) *hasNormal = false;
  if (!m.FaceAlive(f)) return false;
  const Quad& q = m.F[f];
  const int a = q[k], b = q[(k + 1) & 3];
  const Vec3 VPa = vp ? vp[k] : VertexPointT(view, a);
  const Vec3 VPb = vp ? vp[(k + 1) & 3] : VertexPointT(view, b);
  const int g = view.AcrossEdge(f, k);
  if (g < 0) {
    const Vec3 E = 0.5 * (m.P[a] + m.P[b]);
    if (pos) *pos = (VPa + 4.0 * E + VPb) / 6.0;
    return true;
  }
  // edge point of edge j of face h (midpoint on the boundary)
  auto edgePoint = [&](int h, int j) {
    const Vec3& x = m.P[m.F[h][j]];
    const Vec3& y = m.P[m.F[h][(j + 1) & 3]];
    const int o = view.AcrossEdge(h, j);
    return o < 0 ? Vec3(0.5 * (x + y)) : Vec3(0.25 * (x + y + view.Centroid(h) + view.Centroid(o)));
  };
  const Vec3 FPf = view.Centroid(f), FPg = view.Centroid(g);
  const Vec3 E = 0.25 * (m.P[a] + m.P[b] + FPf + FPg);
  const int kb = m.CornerOf(g, b);  // g holds the twin b -> a as its edge kb
  if (kb < 0) return false;
  // 3x3 level-1 grid around E: u from a to b, v towards f (so du x dv follows f's orientation)
  const Vec3 Dpp = edgePoint(f, (k + 1) & 3);   // (u+, v+): f's edge b -> next
  const Vec3 Dmp = edgePoint(f, (k + 3) & 3);   // (u-, v+): f's edge prev -> a
  const Vec3 Dpm = edgePoint(g, (kb + 3) & 3);  // (u+, v-): g's edge prev -> b
  const Vec3 Dmm = edgePoint(g, (kb + 1) & 3);  // (u-, v-): g's edge a -> next
  if (pos) *pos = (16.0 * E + 4.0 * (VPa + VPb + FPf + FPg) + (Dpp + Dmp + Dpm + Dmm)) / 36.0;
  if (normal) {
    Vec3 du = 4.0 * (VPb - VPa) + (Dpp + Dpm - Dmp - Dmm);
    Vec3 dv = 4.0 * (FPf - FPg) + (Dpp + Dmp - Dpm - Dmm);
    Vec3 nr = du.cross(dv);
    double l = nr.norm();
    if (!(l > 0)) return false;
    *normal = nr / l;
    if (hasNormal) *hasNormal = true;
  }
  return true;
}

}  // namespace

// Catmull-Clark vertex point of control vertex v (one refinement step).
Vec3 VertexPoint(const QuadMesh& m, int v) { return VertexPointT(m, v); }
Vec3 VertexPoint(const QuadMemo& m, int v) { return VertexPointT(m, v); }

bool FaceCentreLimit(const QuadMesh& m, int f, Vec3* pos, Vec3* normal) {
  if (!m.FaceAlive(f)) return false;
  Vec3 V[4];
  for (int k = 0; k < 4; ++k) V[k] = VertexPoint(m, m.F[f][k]);
  return FaceCentreLimit(m, f, V, pos, normal);
}
bool FaceCentreLimit(const QuadMesh& m, int f, const Vec3 V[4], Vec3* pos, Vec3* normal) {
  return FaceCentreLimitT(m, f, V, pos, normal);
}
bool FaceCentreLimit(const QuadMemo& m, int f, const Vec3 V[4], Vec3* pos, Vec3* normal) {
  return FaceCentreLimitT(m, f, V, pos, normal);
}
bool EdgeMidLimit(const QuadMesh& m, int f, int k, const Vec3* vp, Vec3* pos, Vec3* normal, bool* hasNormal) {
  return EdgeMidLimitT(m, f, k, vp, pos, normal, hasNormal);
}
bool EdgeMidLimit(const QuadMemo& m, int f, int k, const Vec3* vp, Vec3* pos, Vec3* normal, bool* hasNormal) {
  return EdgeMidLimitT(m, f, k, vp, pos, normal, hasNormal);
}

InterpolationStats SolveInterpolationLocal(QuadMesh& m, const std::vector<int>& W,
                                           const std::vector<Vec3>& targets, double tol, int maxIter) {
  InterpolationStats st;
  // masks once (connectivity is fixed during the solve): flat arrays of (vertex, weight)
  thread_local std::vector<int> offs, idx;
  thread_local std::vector<double> wts, diag;
  thread_local std::vector<std::pair<int, double>> mask;
  offs.assign(1, 0);
  idx.clear();
  wts.clear();
  diag.assign(W.size(), 0.0);
  for (size_t i = 0; i < W.size(); ++i) {
    if (VertexLimitMask(m, W[i], mask))
      for (auto& [j, wt] : mask) {
        if (j == W[i]) diag[i] += wt;
        else { idx.push_back(j); wts.push_back(wt); }
      }
    offs.push_back(int(idx.size()));
  }
  auto residual = [&](size_t i) {
    Vec3 lim = diag[i] * m.P[W[i]];
    for (int e = offs[i]; e < offs[i + 1]; ++e) lim += wts[e] * m.P[idx[e]];
    return Vec3(targets[i] - lim);
  };
  for (int it = 0; it < maxIter; ++it) {
    double maxRes = 0;
    for (size_t i = 0; i < W.size(); ++i) {
      if (!(diag[i] > 0)) continue;
      Vec3 r = residual(i);
      maxRes = std::max(maxRes, r.norm());
      m.MoveVertex(W[i], m.P[W[i]] + r / diag[i]);  // Gauss-Seidel: row i satisfied exactly
    }
    st.iterations = it + 1;
    if (maxRes <= tol) break;
  }
  double maxRes = 0;
  for (size_t i = 0; i < W.size(); ++i)
    if (diag[i] > 0) maxRes = std::max(maxRes, residual(i).norm());
  st.maxResidual = maxRes;
  st.converged = maxRes <= tol;
  return st;
}

InterpolationStats SolveInterpolationGlobal(QuadMesh& m, const std::vector<Vec3>& targets, double tol,
                                            int maxIter) {
  InterpolationStats st;
  const int ns = m.NumVertexSlots();
  std::vector<int> idx(ns, -1), W;
  for (int v = 0; v < ns; ++v)
    if (m.VertAlive(v)) { idx[v] = int(W.size()); W.push_back(v); }
  const int n = int(W.size());
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(size_t(n) * 12);
  std::vector<std::pair<int, double>> mask;
  for (int i = 0; i < n; ++i) {
    if (!VertexLimitMask(m, W[i], mask)) { trip.emplace_back(i, i, 1.0); continue; }
    for (auto& [j, wt] : mask) trip.emplace_back(i, idx[j], wt);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> L(n, n);
  L.setFromTriplets(trip.begin(), trip.end());
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double, Eigen::RowMajor>, Eigen::DiagonalPreconditioner<double>> solver;
  solver.setTolerance(1e-12);
  solver.setMaxIterations(maxIter);
  solver.compute(L);
  Eigen::MatrixXd B(n, 3), X0(n, 3);
  for (int i = 0; i < n; ++i) {
    B.row(i) = targets[W[i]].transpose();
    X0.row(i) = m.P[W[i]].transpose();
  }
  bool ok = solver.info() == Eigen::Success;
  if (ok) {
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXd x = solver.solveWithGuess(B.col(c), X0.col(c));
      if (solver.info() != Eigen::Success || !x.allFinite()) { ok = false; break; }
      X0.col(c) = x;
      st.iterations = std::max(st.iterations, int(solver.iterations()));
    }
  }
  if (ok)
    for (int i = 0; i < n; ++i) m.MoveVertex(W[i], X0.row(i).transpose());
  std::vector<Vec3> tW(n);
  for (int i = 0; i < n; ++i) tW[i] = targets[W[i]];
  InterpolationStats gs = SolveInterpolationLocal(m, W, tW, tol, ok ? 50 : maxIter);
  st.iterations += gs.iterations;
  st.maxResidual = gs.maxResidual;
  st.converged = gs.converged;
  return st;
}

}  // namespace quad
}  // namespace vcgext
