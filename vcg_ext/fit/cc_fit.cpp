#include "vcg_ext/fit/cc_fit.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "vcg_ext/core/memory.h"
#include "vcg_ext/core/progress.h"
#include "vcg_ext/core/stopwatch.h"
#include <Eigen/Geometry>

#include "vcg_ext/fit/fit_internal.h"
#include "vcg_ext/fit/sparse_solver.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext {

namespace {
using SpMat = Eigen::SparseMatrix<double>;
using SpMatR = Eigen::SparseMatrix<double, Eigen::RowMajor>;
}  // namespace

namespace fitdetail {

double PatchArea(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int f, int n) {
  std::vector<Vec3> P((n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) ls.Evaluate(f, double(i) / n, double(j) / n, ctrl, &P[j * (n + 1) + i]);
  double a = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec3& p00 = P[j * (n + 1) + i];
      const Vec3& p10 = P[j * (n + 1) + i + 1];
      const Vec3& p11 = P[(j + 1) * (n + 1) + i + 1];
      const Vec3& p01 = P[(j + 1) * (n + 1) + i];
      a += 0.5 * ((p10 - p00).cross(p11 - p00).norm() + (p11 - p00).cross(p01 - p00).norm());
    }
  return a;
}

Vec3 LimitPointNormal(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int f, double u, double v, Vec3* n) {
  Vec3 P, Du, Dv;
  ls.Evaluate(f, u, v, ctrl, &P, &Du, &Dv);
  Vec3 c = Du.cross(Dv);
  const double scale = Du.squaredNorm() + Dv.squaredNorm();
  if (!(c.norm() > 1e-12 * scale)) {
    const double e = 1e-4;
    Vec3 Q;
    ls.Evaluate(f, std::clamp(u, e, 1 - e), std::clamp(v, e, 1 - e), ctrl, &Q, &Du, &Dv);
    c = Du.cross(Dv);
  }
  const double l = c.norm();
  *n = l > 0 ? Vec3(c / l) : Vec3::Zero();
  return P;
}

bool Project(const EmbreeScene& scene, const Vec3& p, const Vec3& n, double maxDist, Vec3& target, bool* rayHit) {
  *rayHit = false;
  if (n.squaredNorm() > 0) {
    EmbreeScene::Hit h = scene.IntersectLine(p, n, maxDist);
    if (h.valid) { target = h.point; *rayHit = true; return true; }
  }
  EmbreeScene::Hit c = scene.ClosestPoint(p, maxDist);
  if (c.valid) { target = c.point; return true; }
  target = p;
  return false;
}

EmbreeScene::Hit IntersectLineOriented(const EmbreeScene& scene, const std::vector<Vec3>& refN, const Vec3& p,
                                       const Vec3& n, double maxDist) {
  EmbreeScene::Hit best;
  if (!(n.squaredNorm() > 0)) return best;
  const double eps = 1e-5 * maxDist;  // past the hit (Embree works in float)
  for (int side = 0; side < 2; ++side) {
    const Vec3 dir = side == 0 ? n : Vec3(-n);
    double tnear = 0;
    for (int layer = 0; layer < 8; ++layer) {
      EmbreeScene::Hit h = scene.Intersect(p, dir, tnear, maxDist);
      if (!h.valid) break;
      if (best.valid && h.t >= std::abs(best.t)) break;
      if (refN[h.face].dot(n) >= 0) {
        best = h;
        if (side == 1) best.t = -h.t;
        break;
      }
      tnear = h.t + eps;
    }
  }
  return best;
}

Eigen::SparseMatrix<double> LaplacianNormalMatrix(const QuadData& control) {
  const int nV = int(control.V.size());
  std::vector<Eigen::Triplet<double>> tl;
  std::vector<std::vector<int>> nb(nV);
  for (const auto& q : control.F)
    for (int c = 0; c < 4; ++c) { nb[q[c]].push_back(q[(c + 1) % 4]); nb[q[c]].push_back(q[(c + 3) % 4]); }
  for (int v = 0; v < nV; ++v) {
    std::sort(nb[v].begin(), nb[v].end());
    nb[v].erase(std::unique(nb[v].begin(), nb[v].end()), nb[v].end());
    if (nb[v].empty()) continue;
    tl.emplace_back(v, v, 1.0);
    for (int w : nb[v]) tl.emplace_back(v, w, -1.0 / double(nb[v].size()));
  }
  Eigen::SparseMatrix<double> Lap(nV, nV);
  Lap.setFromTriplets(tl.begin(), tl.end());
  return Eigen::SparseMatrix<double>(Lap.transpose() * Lap);
}

}  // namespace fitdetail

namespace {

// Parameters out of range (empty: none).
std::string CheckFitParams(const FitParams& p) {
  if (p.maxIterations < 1 || p.minK < 1 || p.maxK < p.minK || p.samplesPerVertex <= 0 || p.vertexWeight < 0 ||
      p.dampingWeight < 0 || p.smoothWeight < 0 || p.maxProjectionPercent <= 0 || !(p.tangentWeight > 0) ||
      p.dataWeight < 0 || p.sampleWeight < 0 || !(p.dataWeight + p.sampleWeight > 0) || p.footpointSegments < 1) {
    return "invalid fit parameters (iterations >= 1, 1 <= minK <= maxK, positive sample density, distance and "
           "tangent weight, non-negative weights, foot-point segments >= 1)";
  }
  return {};
}

// Where the fit samples (§3.5): k x k cell centres per patch, k from the patch's share of the
// reference's area (samplesPerVertex per reference vertex, clamped to [minK, maxK]); `kOf`, the
// prefix sums `sampleOffs`, the patches' limit areas, and the degenerate patches and the range of
// k in `res`.
void PlanSamples(const LimitSurface& ls, const QuadData& control, const TriData& ref, const FitParams& p,
                 double diag, double refArea, std::vector<int>& kOf, std::vector<int>& sampleOffs,
                 std::vector<double>& area, FitResult& res) {
  const int nF = int(control.F.size());
  kOf.assign(nF, 0);
  area.assign(nF, 0.0);
#pragma omp parallel for schedule(dynamic, 16)
  for (int f = 0; f < nF; ++f) area[f] = fitdetail::PatchArea(ls, control.V, f, 4);
  res.minKUsed = p.maxK;
  res.maxKUsed = 0;
  sampleOffs.assign(nF + 1, 0);
  const double tiny = 1e-14 * diag * diag;
  for (int f = 0; f < nF; ++f) {
    const auto& q = control.F[f];
    double qa = 0.5 * ((control.V[q[1]] - control.V[q[0]]).cross(control.V[q[2]] - control.V[q[0]]).norm() +
                       (control.V[q[2]] - control.V[q[0]]).cross(control.V[q[3]] - control.V[q[0]]).norm());
    Vec3 Pc, Du, Dv;
    ls.Evaluate(f, 0.5, 0.5, control.V, &Pc, &Du, &Dv);
    if (qa <= tiny || Du.cross(Dv).norm() <= tiny || area[f] <= tiny) {
      if (res.firstDegeneratePatch < 0) res.firstDegeneratePatch = f;
      ++res.degeneratePatches;
    }
    int k = int(std::floor(std::sqrt(p.samplesPerVertex * double(ref.V.size()) * area[f] / refArea)));
    k = std::clamp(k, p.minK, p.maxK);
    kOf[f] = k;
    res.minKUsed = std::min(res.minKUsed, k);
    res.maxKUsed = std::max(res.maxKUsed, k);
    sampleOffs[f + 1] = sampleOffs[f] + k * k;
  }
}

// EstimateFitMemoryMb's constants, fitted to what was measured (growth of VmHWM during the fit;
// a fan of quads round one vertex over a 200k-vertex, 400k-triangle reference; default
// parameters; 2026-12-07): valence 64 1.05 GB (estimate 0.99), 128 2.85 GB (2.9), 256 8.6 GB
// (8.3): within -4 ... +2 %, which the 20 % of the available memory CheckMemory leaves covers.
// A stored stencil entry is an index and three weights (28 bytes) plus the vectors' spare
// capacity; a local-block entry six doubles for the faces of one assembly chunk plus its scatter
// position.
constexpr double kFitBytesPerBlockEntry = 32;
constexpr double kFitBytesPerStencilEntry = 48;

}  // namespace

double EstimateFitMemoryMb(const LimitSurface& ls, const FitParams& p, const std::vector<int>& kOf,
                           const std::vector<double>& area, int refVertices) {
  const int nF = ls.NumFaces();
  const double totalArea = std::accumulate(area.begin(), area.end(), 0.0);
  const bool tdm = p.method == FitMethod::TangentDistance && p.dataWeight > 0;
  const double dataRows = tdm ? double(refVertices) / fitdetail::DataStride(p, refVertices) : 0.0;
  double bytes = 0;
  for (int f = 0; f < nF && f < int(kOf.size()); ++f) {
    const double m = ls.NumPatchPoints(f);
    const double share = totalArea > 0 ? area[f] / totalArea : 1.0 / nF;
    const double rows = double(kOf[f]) * kOf[f] + dataRows * share;
    bytes += kFitBytesPerBlockEntry * m * m + kFitBytesPerStencilEntry * rows * m;
  }
  return bytes / (1024.0 * 1024.0);
}

namespace {

// An error when the fit's memory (EstimateFitMemoryMb) would exceed p.maxMemoryMb or, when that
// is 0, 80 % of the memory available now: the kernel would otherwise kill the process (MeshLab
// with it). Names the vertex of highest valence, the usual cause.
std::string CheckFitMemory(const LimitSurface& ls, const FitParams& p, const std::vector<int>& kOf,
                           const std::vector<double>& area, int refVertices) {
  const std::string err =
      CheckMemory(EstimateFitMemoryMb(ls, p, kOf, area, refVertices), p.maxMemoryMb, "the fit");
  if (err.empty()) return err;
  const std::vector<int>& val = ls.Valences();
  const int v = int(std::max_element(val.begin(), val.end()) - val.begin());
  return err + ": its cost grows with the square of the control mesh's valences, and vertex " + std::to_string(v) +
         " has " + std::to_string(val[v]) + " edges; remesh the control mesh round it (or fit a coarser reference)";
}

// The fixed rows of the fit: the stencils (A, ADu, ADv) of the patch samples [0, nS), then one
// row per control vertex at its corner (system (1)); each row's face and weight.
void StencilRows(const LimitSurface& ls, const QuadData& control, const FitParams& p, const std::vector<int>& kOf,
                 const std::vector<int>& sampleOffs, std::vector<fitdetail::StencilRow>& rows,
                 std::vector<double>& weight, std::vector<int>& rowFace) {
  const int nV = int(control.V.size()), nF = int(control.F.size());
  const int nS = sampleOffs[nF], nRows = nS + nV;
  using Row = fitdetail::StencilRow;
  rows.assign(nRows, Row());
  weight.assign(nRows, 1.0);
  rowFace.assign(nRows, -1);
#pragma omp parallel for schedule(dynamic, 16)
  for (int f = 0; f < nF; ++f) {
    LimitStencil st;
    const int k = kOf[f];
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        ls.Stencil(f, (i + 0.5) / k, (j + 0.5) / k, st, 1);
        Row& r = rows[sampleOffs[f] + j * k + i];
        rowFace[sampleOffs[f] + j * k + i] = f;
        r.idx = st.index; r.w = st.P; r.du = st.Du; r.dv = st.Dv;
      }
  }
  {
    std::vector<std::pair<int, int>> vc(nV, {-1, -1});
    for (int f = 0; f < nF; ++f)
      for (int c = 0; c < 4; ++c)
        if (vc[control.F[f][c]].first < 0) vc[control.F[f][c]] = {f, c};
    LimitStencil st;
    for (int v = 0; v < nV; ++v) {
      Row& r = rows[nS + v];
      if (vc[v].first < 0) {  // isolated vertex: keep it where it is
        r.idx = {v}; r.w = {1.0}; r.du = {0.0}; r.dv = {0.0};
        weight[nS + v] = 0.0;
        continue;
      }
      double u, w;
      ls.CornerUV(vc[v].first, vc[v].second, u, w);
      ls.Stencil(vc[v].first, u, w, st, 1);
      rowFace[nS + v] = vc[v].first;
      r.idx = st.index; r.w = st.P; r.du = st.Du; r.dv = st.Dv;
      weight[nS + v] = p.vertexWeight;
    }
  }
}

// The stencil rows as sparse matrices: positions A, derivatives ADu and ADv (rows x nV). Frees
// `rows`.
void StencilMatrices(std::vector<fitdetail::StencilRow>& rows, int nV, SpMatR& A, SpMatR& ADu, SpMatR& ADv) {
  const int nRows = int(rows.size());
  std::vector<Eigen::Triplet<double>> tA, tU, tV;
  size_t nnz = 0;
  for (const auto& r : rows) nnz += r.idx.size();
  tA.reserve(nnz); tU.reserve(nnz); tV.reserve(nnz);
  for (int i = 0; i < nRows; ++i)
    for (size_t j = 0; j < rows[i].idx.size(); ++j) {
      tA.emplace_back(i, rows[i].idx[j], rows[i].w[j]);
      tU.emplace_back(i, rows[i].idx[j], rows[i].du[j]);
      tV.emplace_back(i, rows[i].idx[j], rows[i].dv[j]);
    }
  rows.clear();
  rows.shrink_to_fit();
  A.resize(nRows, nV); ADu.resize(nRows, nV); ADv.resize(nRows, nV);
  A.setFromTriplets(tA.begin(), tA.end());
  ADu.setFromTriplets(tU.begin(), tU.end());
  ADv.setFromTriplets(tV.begin(), tV.end());
}

// One projection of the point-to-point fit: every row's limit point P moved along its limit
// normal onto the input (T); the RMS distance of the patch samples [0, nS) and their share without
// a hit (missFraction).
double ProjectRows(const EmbreeScene& scene, const Eigen::MatrixXd& P, const Eigen::MatrixXd& Du,
                   const Eigen::MatrixXd& Dv, int nS, double maxDist, Eigen::MatrixXd& T, double& missFraction) {
  const int nRows = int(P.rows());
  double sum = 0, wsum = 0;
  long misses = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum, wsum, misses)
  for (int i = 0; i < nRows; ++i) {
    Vec3 pi = P.row(i).transpose();
    Vec3 n = Vec3(Du.row(i).transpose()).cross(Vec3(Dv.row(i).transpose()));
    double nn = n.norm();
    n = nn > 0 ? Vec3(n / nn) : Vec3::Zero();
    Vec3 t;
    bool hit = false;
    fitdetail::Project(scene, pi, n, maxDist, t, &hit);  // t: the target, pi itself without one
    if (i < nS) {
      if (!hit) ++misses;
      sum += (t - pi).squaredNorm();
      wsum += 1;
    }
    T.row(i) = t.transpose();
  }
  missFraction = double(misses) / std::max(nS, 1);
  return std::sqrt(sum / std::max(wsum, 1.0));
}

// The paper's literal §3.5 (FitMethod::PointToPoint): every row pulled to its projection along
// the limit normal, one factorization, project -> solve until the RMS stops improving. The best
// iterate in `best` (nV x 3); false with res.error set on a singular system or a cage far off.
bool FitPointToPoint(const QuadData& control, const EmbreeScene& scene, const FitParams& p,
                     std::vector<fitdetail::StencilRow>& rows, const std::vector<double>& weight, int nS,
                     double maxDist, Clock::time_point t0, Progress& prog, Eigen::MatrixXd& best, FitResult& res) {
  const int nV = int(control.V.size()), nRows = int(rows.size());
  SpMatR A, ADu, ADv;
  StencilMatrices(rows, nV, A, ADu, ADv);
  Eigen::VectorXd W = Eigen::Map<const Eigen::VectorXd>(weight.data(), nRows);
  SpMat AtW = SpMat(A.transpose()) * W.asDiagonal();
  SpMat M = AtW * A;
  const double meanDiag = M.diagonal().sum() / nV;
  const double lambda = p.dampingWeight * meanDiag, mu = p.smoothWeight * meanDiag;
  if (mu > 0) M += mu * fitdetail::LaplacianNormalMatrix(control);
  if (lambda > 0) {
    SpMat I(nV, nV);
    I.setIdentity();
    M += lambda * I;
  }
  res.secondsSetup = Since(t0);
  prog(20, "Fit: factorizing", true);
  auto tf = Clock::now();
  fitdetail::SpdSolver solver(int(M.rows()));
  solver.compute(M);
  res.secondsFactor = Since(tf);
  if (solver.info() != Eigen::Success) {
    res.error = "the fitting system is singular (" + std::to_string(nV) + " control vertices, " +
                std::to_string(nS) + " samples): increase samplesPerVertex or dampingWeight";
    return false;
  }

  // ---- iterate project -> solve.
  Eigen::MatrixXd X(nV, 3);
  for (int v = 0; v < nV; ++v) X.row(v) = control.V[v].transpose();
  best = X;
  double bestRms = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd T(nRows, 3);
  for (int it = 0; it <= p.maxIterations; ++it) {
    auto tp = Clock::now();
    Eigen::MatrixXd P = A * X, Du = ADu * X, Dv = ADv * X;
    const double rms = ProjectRows(scene, P, Du, Dv, nS, maxDist, T, res.rayMissFraction);
    res.secondsProject += Since(tp);
    if (it == 0 && res.rayMissFraction > p.maxMissFraction) {
      res.error = "the control mesh is far from the reference: " +
                  std::to_string(int(std::round(100 * res.rayMissFraction))) +
                  "% of the limit samples find no reference surface along their normal within " +
                  std::to_string(p.maxProjectionPercent) + "% of the bbox diagonal";
      return false;
    }
    res.rmsPerIteration.push_back(rms);
    if (fitdetail::StopIterating(rms, bestRms, X, best, p, it)) break;
    prog(20 + 80.0 * (it + 1) / (p.maxIterations + 1), "Fit: project and solve");
    auto ts = Clock::now();
    Eigen::MatrixXd rhs = AtW * T;
    if (lambda > 0) rhs += lambda * X;
    X = solver.solve(rhs);
    res.secondsSolve += Since(ts);
    ++res.iterations;
    if (!X.allFinite()) { X = best; break; }
  }
  return true;
}

}  // namespace

FitResult FitCatmullClark(const QuadData& control, const TriData& ref, const EmbreeScene& scene, const FitParams& p,
                          vcg::CallBackPos* cb) {
  FitResult res;
  const auto t0 = Clock::now();
  Progress prog(cb);
  if (ref.V.empty() || ref.F.empty()) { res.error = "the reference mesh is empty"; return res; }
  if (!scene.Ok()) { res.error = "the reference ray-casting scene is not valid: " + scene.Error(); return res; }
  if (control.F.empty()) { res.error = "the control mesh has no faces"; return res; }
  for (size_t i = 0; i < control.V.size(); ++i)
    if (!control.V[i].allFinite()) {
      res.error = "control vertex " + std::to_string(i) + " has NaN or infinite coordinates";
      return res;
    }
  res.error = CheckFitParams(p);
  if (!res.error.empty()) return res;
  LimitSurface ls = LimitSurface::FromQuads(control);
  if (!ls.Ok()) { res.error = "control mesh: " + ls.Error(); return res; }
  const int nV = int(control.V.size()), nF = int(control.F.size());
  res.patches = nF;
  res.irregularVertices = ls.NumIrregularVertices();
  const double diag = BBoxDiagonal(ref.V);
  const double maxDist = p.maxProjectionPercent / 100.0 * diag;
  const double refArea = TotalArea(ref);
  if (!(refArea > 0)) { res.error = "the reference mesh has zero area"; return res; }
  prog(0, "Fit: sampling patches", true);

  // ---- samples: k×k cell centres per patch + one corner sample per control vertex.
  std::vector<int> kOf, sampleOffs;
  std::vector<double> area;
  PlanSamples(ls, control, ref, p, diag, refArea, kOf, sampleOffs, area, res);
  res.error = CheckFitMemory(ls, p, kOf, area, int(ref.V.size()));
  if (!res.error.empty()) return res;
  const int nS = sampleOffs[nF];
  res.samples = nS;

  // Stencils (rows of A, ADu, ADv), computed in parallel per patch.
  std::vector<fitdetail::StencilRow> rows;
  std::vector<double> weight;
  std::vector<int> rowFace;
  StencilRows(ls, control, p, kOf, sampleOffs, rows, weight, rowFace);
  Eigen::MatrixXd X;  // the fitted control points (nV x 3)
  if (p.method == FitMethod::TangentDistance) {
    X.resize(nV, 3);
    for (int v = 0; v < nV; ++v) X.row(v) = control.V[v].transpose();
    res.secondsSetup = Since(t0);
    const SpMat LtL = p.smoothWeight > 0 ? fitdetail::LaplacianNormalMatrix(control) : SpMat(nV, nV);
    res.error = fitdetail::FitTangentDistance(ls, ref, scene, p, rows, rowFace, weight, nS, maxDist, LtL, X, res, prog);
    if (!res.error.empty()) return res;
  } else if (!FitPointToPoint(control, scene, p, rows, weight, nS, maxDist, t0, prog, X, res)) {
    return res;
  }
  res.control.F = control.F;
  res.control.V.resize(nV);
  for (int v = 0; v < nV; ++v) res.control.V[v] = X.row(v).transpose();
  res.seconds = Since(t0);
  prog(100, "Fit: done", true);
  return res;
}

}  // namespace vcgext
