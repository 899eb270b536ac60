// Tangent-distance iterations of the final Catmull-Clark fit (FitMethod::TangentDistance).
//
// Energy (linearized at the current iterate, one Gauss-Newton step per iteration):
//   E(X) = Σ_rows ω_r (s_r(X) − t_r)ᵀ Q_r (s_r(X) − t_r) + λ |X − X_prev|²,
//   Q_r = n_r n_rᵀ + w_t (I − n_r n_rᵀ)
// with, for
//  - the paper's limit samples s(f,u,v) (fixed (u,v)) and the vertex rows of system (1):
//    t = projection phi along the limit normal, n = normal of the reference triangle hit;
//  - one row per reference vertex x (weight dataWeight): s = limit point at the foot point
//    (f,u,v) of x (closest point of a tessellation, refined by Gauss-Newton on the exact limit),
//    t = x, n = limit normal at the foot point.
// Unknowns are ordered coordinate-major (x of all vertices, then y, then z). The sparsity pattern
// (union over faces of support(f)², ⊗ 3×3) is fixed, so the solver (sparse_solver.h: CHOLMOD's
// supernodal Cholesky for large systems, else SimplicialLDLT) analyses it once and refactorizes
// every iteration. Assembly is per face (dense local blocks, added in face order).
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/IterativeLinearSolvers>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "vcg_ext/core/stopwatch.h"
#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/fit_internal.h"
#include "vcg_ext/fit/sparse_solver.h"

namespace vcgext {
namespace fitdetail {

namespace {
using SpMat = Eigen::SparseMatrix<double>;

// One least-squares row: limit point Σ w[k]·X[idx[k]] pulled to `target` with metric Q.
struct Constraint {
  const int* idx = nullptr;
  const double* w = nullptr;
  int n = 0;
  Vec3 target = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  double weight = 0;
};

// Position of entry (row, col) in the compressed column `col` of P (must exist).
int EntryPos(const SpMat& P, int row, int col) {
  const int* b = P.innerIndexPtr() + P.outerIndexPtr()[col];
  const int* e = P.innerIndexPtr() + P.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(b, e, row);
  return (it != e && *it == row) ? int(it - P.innerIndexPtr()) : -1;
}

// The system's fixed sparsity: P (nV×nV) is the union over faces of support(f)² (the 3nV system
// has pattern P in each of its 3×3 blocks: BlockPattern).
struct TdmPattern {
  std::vector<std::vector<int>> sup;  // per face: its control points, sorted
  SpMat P;
  std::vector<std::vector<int>> pos;  // per face: position in P of (sup[a], sup[b]), a-major
  std::vector<int> diagPos;           // per vertex: position of (v, v) in P
  std::vector<std::pair<int, double>> lapEntries;  // LᵀL's entries (position in P, value)
};

// Face supports (stencil indices are the patch's control points), widened by any fixed row's
// indices that are not in them (defensive).
std::vector<std::vector<int>> FaceSupports(const LimitSurface& ls, const std::vector<StencilRow>& rows,
                                           const std::vector<int>& rowFace) {
  const int nF = ls.NumFaces(), nR = int(rows.size());
  std::vector<std::vector<int>> sup(nF);
  LimitStencil st;
  for (int f = 0; f < nF; ++f) {
    ls.Stencil(f, 0.5, 0.5, st, 0);
    sup[f] = st.index;
  }
  for (int r = 0; r < nR; ++r) {
    const int f = rowFace[r];
    if (f < 0) continue;
    for (int i : rows[r].idx)
      if (!std::binary_search(sup[f].begin(), sup[f].end(), i)) {
        sup[f].insert(std::upper_bound(sup[f].begin(), sup[f].end(), i), i);
      }
  }
  return sup;
}

// P: a zero for each vertex's diagonal and each pair of one face's support.
SpMat SupportPattern(int nV, const std::vector<std::vector<int>>& sup) {
  SpMat P(nV, nV);
  std::vector<Eigen::Triplet<double>> t;
  for (int v = 0; v < nV; ++v) t.emplace_back(v, v, 0.0);
  for (const auto& s : sup)
    for (int a : s)
      for (int b : s) t.emplace_back(a, b, 0.0);
  P.setFromTriplets(t.begin(), t.end());
  P.makeCompressed();
  return P;
}

// H: pattern P in each of the 3×3 blocks; columns ordered c-major, rows r-major within a column.
SpMat BlockPattern(const SpMat& P) {
  const int nV = int(P.rows());
  SpMat H(3 * nV, 3 * nV);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(size_t(9) * P.nonZeros());
  for (int c = 0; c < 3; ++c)
    for (int b = 0; b < nV; ++b)
      for (int r = 0; r < 3; ++r)
        for (int q = P.outerIndexPtr()[b]; q < P.outerIndexPtr()[b + 1]; ++q)
          t.emplace_back(r * nV + P.innerIndexPtr()[q], c * nV + b, 1.0);
  H.setFromTriplets(t.begin(), t.end());
  H.makeCompressed();
  return H;
}

TdmPattern BuildPattern(const LimitSurface& ls, const std::vector<StencilRow>& rows,
                        const std::vector<int>& rowFace, const SpMat& LtL, bool smooth) {
  const int nV = ls.NumVertices(), nF = ls.NumFaces();
  TdmPattern pat;
  pat.sup = FaceSupports(ls, rows, rowFace);
  pat.P = SupportPattern(nV, pat.sup);
  pat.pos.resize(nF);
  for (int f = 0; f < nF; ++f) {
    const auto& s = pat.sup[f];
    const int m = int(s.size());
    pat.pos[f].resize(size_t(m) * m);
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) pat.pos[f][size_t(a) * m + b] = EntryPos(pat.P, s[a], s[b]);
  }
  pat.diagPos.resize(nV);
  for (int v = 0; v < nV; ++v) pat.diagPos[v] = EntryPos(pat.P, v, v);
  // Smoothness term: entries of LᵀL (2-ring of the control net, inside the patch supports).
  if (smooth)
    for (int c = 0; c < LtL.outerSize(); ++c)
      for (SpMat::InnerIterator it(LtL, c); it; ++it) {
        const int q = EntryPos(pat.P, int(it.row()), int(it.col()));
        if (q >= 0) pat.lapEntries.emplace_back(q, it.value());
      }
  return pat;
}

// The rows of one iteration: the fixed rows [0, nR) then one per reference vertex.
struct TdmRows {
  std::vector<Constraint> cons;
  std::vector<LimitStencil> dataSt;       // per reference vertex: stencil at its foot point
  std::vector<int> dataFace;              // per reference vertex: its foot point's face (-1: none yet)
};

// Squared distances summed in row order (the sum does not depend on thread scheduling).
struct SquaredSum {
  double sum = 0, count = 0;
};
SquaredSum SumInOrder(const std::vector<double>& sq) {  // entries < 0 are skipped
  SquaredSum s;
  for (double d : sq)
    if (d >= 0) { s.sum += d; s.count += 1; }
  return s;
}

// (a) Fixed samples and vertex rows: projection phi along the limit normal. Returns the samples'
// squared distances; `misses` counts the samples [0, nS) whose ray found no reference.
SquaredSum ProjectFixedRows(const std::vector<Vec3>& ctrl, const std::vector<StencilRow>& rows,
                            const std::vector<int>& rowFace, const std::vector<double>& rowWeight, int nS,
                            const EmbreeScene& scene, const std::vector<Vec3>& refN, double maxDist,
                            double sampleWeight, std::vector<Constraint>& cons, long& misses) {
  const int nR = int(rows.size());
  std::vector<double> sSq(size_t(nR), -1.0);  // per sample row (summed in order below)
  long miss = 0;
#pragma omp parallel for schedule(static) reduction(+ : miss)
  for (int r = 0; r < nR; ++r) {
    const StencilRow& row = rows[r];
    Constraint& c = cons[r];
    c.idx = row.idx.data();
    c.w = row.w.data();
    c.n = int(row.idx.size());
    c.weight = 0;
    if (rowFace[r] < 0 || rowWeight[r] <= 0) continue;
    Vec3 P0 = Vec3::Zero(), Du = Vec3::Zero(), Dv = Vec3::Zero();
    for (int k = 0; k < c.n; ++k) {
      const Vec3& q = ctrl[row.idx[k]];
      P0 += row.w[k] * q;
      Du += row.du[k] * q;
      Dv += row.dv[k] * q;
    }
    Vec3 n = Du.cross(Dv);
    const double nn = n.norm();
    EmbreeScene::Hit h;
    if (nn > 0) h = scene.IntersectLine(P0, n / nn, maxDist);
    if (!h.valid) {
      if (r < nS) ++miss;
      h = scene.ClosestPoint(P0, maxDist);
    }
    if (!h.valid) continue;  // no target: no pull
    // A hit on a sheet facing the other way (the far side of a thin part, e.g. an ear) is the
    // wrong correspondence: no pull from this row (the reference-vertex rows cover that part).
    // (Passing through to the nearest consistently oriented sheet, as the bake does, was
    // measured worse for the fit: 3.88 vs 3.75 permille on bunny00.)
    if (nn > 0 && refN[h.face].dot(n) < 0) continue;
    c.target = h.point;
    c.normal = refN[h.face];
    c.weight = rowWeight[r] * sampleWeight;
    if (r < nS) sSq[r] = (h.point - P0).squaredNorm();
  }
  misses = miss;
  return SumInOrder(sSq);
}

// The foot point (face, uv) of x on the tessellated limit's hit `h`, refined by Gauss-Newton on
// |s(u,v) − x|² over the exact limit, clamped to the patch.
Eigen::Vector2d FootPointUV(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const Vec3& x,
                            const EmbreeScene::Hit& h, int Nf, int& f) {
  const int triPerFace = 2 * Nf * Nf;
  f = h.face / triPerFace;
  const int local = h.face % triPerFace, cell = local / 2;
  const double ci = cell % Nf, cj = cell / Nf;
  Eigen::Vector2d c0(ci, cj), c1, c2;
  if (local % 2 == 0) { c1 = {ci + 1, cj}; c2 = {ci + 1, cj + 1}; }
  else { c1 = {ci + 1, cj + 1}; c2 = {ci, cj + 1}; }
  Eigen::Vector2d uv = ((1 - h.u - h.v) * c0 + h.u * c1 + h.v * c2) / Nf;
  Vec3 S, Du, Dv;
  for (int g = 0; g < 3; ++g) {
    ls.Evaluate(f, uv[0], uv[1], ctrl, &S, &Du, &Dv);
    const Vec3 d = x - S;
    Eigen::Matrix2d JtJ;
    JtJ << Du.dot(Du), Du.dot(Dv), Du.dot(Dv), Dv.dot(Dv);
    const Eigen::Vector2d g2(Du.dot(d), Dv.dot(d));
    // singular (Du, Dv parallel or zero), relative to |Du|² |Dv|² so that a mesh's scale does not
    // decide it: the absolute 1e-30 this was stopped every foot point of a mesh 1e-9 across
    if (!(std::abs(JtJ.determinant()) > 1e-30 * JtJ(0, 0) * JtJ(1, 1))) break;
    const Eigen::Vector2d step = JtJ.inverse() * g2;
    uv = (uv + step).cwiseMax(0.0).cwiseMin(1.0);
    if (step.norm() < 1e-6) break;
  }
  return uv;
}

// (b) Reference vertices (every dataStride-th): foot points on the current limit, pulled to x
// along the limit normal there. Returns their squared distances.
SquaredSum FootPointRows(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                         const FitParams& p, int dataStride, double maxDist, int nR, TdmRows& R) {
  const int nRef = int(ref.V.size());
  LimitTessellation tess = TessellateLimit(ls, ctrl, p.footpointSegments);
  EmbreeScene limScene(tess.mesh);
  std::vector<double> dSq(size_t(nRef), -1.0);  // per reference vertex (summed in order below)
#pragma omp parallel
  {
    int hint = -1;  // the previous vertex's foot face (ClosestPoint's hint: the same answer, sooner)
#pragma omp for schedule(dynamic, 256)
    for (int i = 0; i < nRef; ++i) {
      Constraint& c = R.cons[size_t(nR) + i];
      c.weight = 0;
      if (p.dataWeight <= 0 || i % dataStride) continue;
      const Vec3& x = ref.V[i];
      EmbreeScene::Hit h = limScene.ClosestPoint(x, maxDist, hint);
      if (!h.valid) continue;
      hint = h.face;
      int f = -1;
      const Eigen::Vector2d uv = FootPointUV(ls, ctrl, x, h, p.footpointSegments, f);
      LimitStencil& st = R.dataSt[i];
      ls.Stencil(f, uv[0], uv[1], st, 1);
      Vec3 S = Vec3::Zero(), Du = Vec3::Zero(), Dv = Vec3::Zero();
      for (int k = 0; k < st.Size(); ++k) {
        const Vec3& q = ctrl[st.index[k]];
        S += st.P[k] * q;
        Du += st.Du[k] * q;
        Dv += st.Dv[k] * q;
      }
      Vec3 n = Du.cross(Dv);
      if (!(n.norm() > 0)) n = tess.normal[tess.mesh.F[h.face][0]];
      if (!(n.norm() > 0)) continue;
      R.dataFace[i] = f;
      c.idx = st.index.data();
      c.w = st.P.data();
      c.n = st.Size();
      c.target = x;
      c.normal = n.normalized();
      c.weight = p.dataWeight * dataStride;
      dSq[i] = (x - S).squaredNorm();
    }
  }
  return SumInOrder(dSq);
}

// The normal equations' symmetric 3×3 blocks (00 01 02 11 12 22, each on pattern P) and right side.
struct TdmNormalEquations {
  std::vector<double> val[6];
  Eigen::VectorXd rhs;
};

// The active rows grouped by face (counting sort, row order kept within a face): `order` holds
// row indices, face f's are order[start[f] .. start[f+1]).
void RowsByFace(const TdmRows& R, const std::vector<int>& rowFace, int nR, int nF, std::vector<int>& order,
                std::vector<int>& start) {
  order.assign(R.cons.size(), 0);
  start.assign(nF + 1, 0);
  auto faceOf = [&](size_t k) { return k < size_t(nR) ? rowFace[k] : R.dataFace[k - nR]; };
  for (size_t k = 0; k < R.cons.size(); ++k)
    if (R.cons[k].weight > 0) ++start[faceOf(k) + 1];
  for (int f = 0; f < nF; ++f) start[f + 1] += start[f];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (size_t k = 0; k < R.cons.size(); ++k)
    if (R.cons[k].weight > 0) order[fill[faceOf(k)]++] = int(k);
}

// One face's dense local block: lower halves of the 6 symmetric components (L, m×m each) and the
// right side (B, 3×m) of the rows order[q0 .. q1).
void FaceBlock(const std::vector<int>& S, const std::vector<Constraint>& cons, const std::vector<int>& order,
               int q0, int q1, double wt, std::array<std::vector<double>, 6>& L, std::vector<double>& B) {
  const int m = int(S.size());
  for (auto& l : L) l.assign(size_t(m) * m, 0.0);
  B.assign(size_t(3) * m, 0.0);
  std::vector<int> loc;
  for (int q = q0; q < q1; ++q) {
    const Constraint& c = cons[order[q]];
    loc.resize(c.n);
    bool ok = true;
    for (int k = 0; k < c.n; ++k) {
      auto itS = std::lower_bound(S.begin(), S.end(), c.idx[k]);
      if (itS == S.end() || *itS != c.idx[k]) { ok = false; break; }
      loc[k] = int(itS - S.begin());
    }
    if (!ok) continue;  // cannot happen: Bfr stencils use the face's patch points
    const Vec3& n = c.normal;
    Eigen::Matrix3d Q = c.weight * (wt * Eigen::Matrix3d::Identity() + (1 - wt) * n * n.transpose());
    const Vec3 Qt = Q * c.target;
    const double q6[6] = {Q(0, 0), Q(0, 1), Q(0, 2), Q(1, 1), Q(1, 2), Q(2, 2)};
    for (int a = 0; a < c.n; ++a) {
      const double wa = c.w[a];
      if (wa == 0) continue;
      const size_t ra = size_t(loc[a]) * m;
      for (int b = 0; b <= a; ++b) {  // lower half (loc is increasing); mirrored when scattered
        const double ww = wa * c.w[b];
        const size_t e = ra + loc[b];
        for (int s = 0; s < 6; ++s) L[s][e] += ww * q6[s];
      }
      for (int d = 0; d < 3; ++d) B[size_t(d) * m + loc[a]] += wa * Qt[d];
    }
  }
}

// Adds face f's local block into the normal equations (both halves).
void ScatterFaceBlock(const TdmPattern& pat, int f, int nV, const std::array<std::vector<double>, 6>& L,
                      const std::vector<double>& B, TdmNormalEquations& ne) {
  const std::vector<int>& S = pat.sup[f];
  const int m = int(S.size());
  const int* pf = pat.pos[f].data();
  for (int a = 0; a < m; ++a)
    for (int b = 0; b <= a; ++b) {
      const size_t e = size_t(a) * m + b;
      const int p1 = pf[e], p2 = pf[size_t(b) * m + a];
      for (int s = 0; s < 6; ++s) {
        ne.val[s][p1] += L[s][e];
        if (a != b) ne.val[s][p2] += L[s][e];
      }
    }
  for (int d = 0; d < 3; ++d)
    for (int a = 0; a < m; ++a) ne.rhs[d * nV + S[a]] += B[size_t(d) * m + a];
}

// Assembly per face (dense local blocks). Local blocks are computed in parallel for a chunk of
// faces, then added in face order: the floating-point sums (hence the fit) do not depend on thread
// scheduling. (Atomic scatter made repeated runs differ, elephant.off: RMS 3.29-3.59 permille.)
void Assemble(const TdmPattern& pat, const TdmRows& R, const std::vector<int>& rowFace, int nR, int nV,
              double wt, TdmNormalEquations& ne) {
  const int nF = int(pat.sup.size());
  std::vector<int> order, start;
  RowsByFace(R, rowFace, nR, nF, order, start);
  for (auto& v : ne.val) std::fill(v.begin(), v.end(), 0.0);
  ne.rhs.setZero();
  const int chunk = 256;
  std::vector<std::array<std::vector<double>, 6>> Lc(chunk);
  std::vector<std::vector<double>> Bc(chunk);
  for (int f0 = 0; f0 < nF; f0 += chunk) {
    const int f1 = std::min(nF, f0 + chunk);
#pragma omp parallel for schedule(dynamic, 4)
    for (int f = f0; f < f1; ++f) {
      if (start[f] == start[f + 1]) { Bc[f - f0].clear(); continue; }
      FaceBlock(pat.sup[f], R.cons, order, start[f], start[f + 1], wt, Lc[f - f0], Bc[f - f0]);
    }
    for (int f = f0; f < f1; ++f)
      if (!Bc[f - f0].empty()) ScatterFaceBlock(pat, f, nV, Lc[f - f0], Bc[f - f0], ne);
  }
}

// Damping λ = dampingScale · dampingWeight · mean diagonal (Levenberg; vanishes at the fixed
// point) and smoothness μ·LᵀL (μ = smoothWeight · mean diagonal), then H's values from the
// blocks. Returns λ.
double FillSystem(const TdmPattern& pat, const FitParams& p, double dampingScale, int nV, TdmNormalEquations& ne,
                  SpMat& H) {
  double diagSum = 0;
  for (int v = 0; v < nV; ++v)
    diagSum += ne.val[0][pat.diagPos[v]] + ne.val[3][pat.diagPos[v]] + ne.val[5][pat.diagPos[v]];
  const double lambda = dampingScale * p.dampingWeight * diagSum / (3.0 * nV);
  const double mu = p.smoothWeight * diagSum / (3.0 * nV);
  for (const auto& [q, x] : pat.lapEntries)
    for (int s : {0, 3, 5}) ne.val[s][q] += mu * x;
  const int sym[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  const SpMat& P = pat.P;
  double* hv = H.valuePtr();
  size_t k = 0;
  for (int c = 0; c < 3; ++c)
    for (int b = 0; b < nV; ++b)
      for (int r = 0; r < 3; ++r)
        for (int q = P.outerIndexPtr()[b]; q < P.outerIndexPtr()[b + 1]; ++q) {
          double v = ne.val[sym[r][c]][q];
          if (r == c && P.innerIndexPtr()[q] == b) v += lambda;
          hv[k++] = v;
        }
  return lambda;
}

// Which iterate the fit returns and when it stops (FitParams::keepLowestDataRms, damping retries;
// docs/fit.md "Which iterate is kept", "Damping").
struct IterateChoice {
  Eigen::MatrixXd best;  // the objective's choice
  double bestObj = std::numeric_limits<double>::infinity();
  int bestIteration = -1;  // the projection of `best`
  Eigen::MatrixXd kept;    // keepLowestDataRms: the lowest data RMS's
  double keptDataRms = std::numeric_limits<double>::infinity();
  double lastDataRms = std::numeric_limits<double>::infinity();  // the previous accepted projection's
  double dampingScale = 1;  // x10 after each solve that raised the objective
  int retries = 0;
  bool reverted = false;
};

enum class Step { Solve, Retry, Stop };

// After the projection of iterate X (objective `obj`, data RMS `dRms`): keep, revert or stop.
Step ChooseStep(IterateChoice& ch, double obj, double dRms, int it, const FitParams& p, Eigen::MatrixXd& X,
                FitResult& res) {
  if (p.keepLowestDataRms && dRms < ch.keptDataRms) {
    ch.keptDataRms = dRms;
    ch.kept = X;
    res.keptIteration = int(res.dataRmsPerIteration.size()) - 1;
  }
  if (ch.reverted) {
    ch.reverted = false;  // X is the best iterate again: solve from it with the larger damping
    return Step::Solve;
  }
  if (!(obj < ch.bestObj) && ch.retries < p.dampingRetries && it < p.maxIterations) {
    // The last solve raised the objective: back to the best iterate, 10x the damping
    // (Levenberg-Marquardt; docs/fit.md "Damping").
    X = ch.best;
    ch.dampingScale *= 10;
    ++ch.retries;
    ++res.dampingRetries;
    ch.reverted = true;
    return Step::Retry;
  }
  const double before = ch.bestObj;
  bool stop = StopIterating(obj, ch.bestObj, X, ch.best, p, it);
  if (ch.bestObj < before) ch.bestIteration = int(res.objectivePerIteration.size()) - 1;
  // keepLowestDataRms: the returned iterate is the data RMS's, so the objective's small
  // improvement alone does not end the fit while the data RMS still improves by minImprovement
  // (bunny00 @1000: the objective improved by < 1 % with the data RMS 3 % lower, one more
  // solve took the report from 0.353 to 0.344 per mille; docs/fit.md "Which iterate is kept")
  if (stop && p.keepLowestDataRms && obj < before && it < p.maxIterations &&
      dRms < (1 - p.minImprovement) * ch.lastDataRms)
    stop = false;
  ch.lastDataRms = dRms;
  return stop ? Step::Stop : Step::Solve;
}

// H sol = rhs: by the factorization of H, or (reuse, once factored) by conjugate gradients from
// the current iterate X preconditioned with the latest factorization, which is redone when they
// do not converge in 50 steps, and at the next solve when they took more than 10
// (FitParams::reuseFactorizationFrom). False when the factorization fails.
bool Solve(const SpMat& H, const Eigen::VectorXd& rhs, const Eigen::MatrixXd& X, bool reuse, bool& factored,
           SpdSolver& solver, Eigen::VectorXd& sol, FitResult& res) {
  if (reuse && factored) {
    Eigen::ConjugateGradient<SpMat, Eigen::Lower | Eigen::Upper, FactorPreconditioner> cg;
    cg.preconditioner().Use(&solver, H.rows());
    cg.setTolerance(1e-10);
    cg.setMaxIterations(50);
    cg.compute(H);
    const int nV = int(X.rows());
    Eigen::VectorXd x0(3 * nV);
    for (int c = 0; c < 3; ++c) x0.segment(c * nV, nV) = X.col(c);
    sol = cg.solveWithGuess(rhs, x0);
    res.conjugateGradientSteps += int(cg.iterations());
    if (cg.iterations() > 10) factored = false;  // the factorization has aged: redo it next time
    if (cg.info() == Eigen::Success) return true;
  }
  solver.factorize(H);
  if (solver.info() != Eigen::Success) return false;
  factored = true;
  ++res.factorizations;
  sol = solver.solve(rhs);
  return true;
}

}  // namespace

std::string FitTangentDistance(const LimitSurface& ls, const TriData& ref, const EmbreeScene& scene,
                               const FitParams& p, const std::vector<StencilRow>& rows,
                               const std::vector<int>& rowFace, const std::vector<double>& rowWeight, int nS,
                               double maxDist, const SpMat& LtL, Eigen::MatrixXd& X, FitResult& res,
                               Progress& prog) {
  const int nV = ls.NumVertices(), nR = int(rows.size()), nRef = int(ref.V.size());
  // maxDataRows: every dataStride-th reference vertex gets a row (weighted dataStride times).
  const int dataStride = DataStride(p, nRef);
  const auto refN = FaceNormals(ref);
  TdmPattern pat = BuildPattern(ls, rows, rowFace, LtL, p.smoothWeight > 0);
  SpMat H = BlockPattern(pat.P);
  SpdSolver solver(int(H.rows()));
  solver.analyzePattern(H);
  const bool reuse = p.reuseFactorizationFrom > 0 && H.rows() >= p.reuseFactorizationFrom;
  bool factored = false;

  TdmRows R;
  R.cons.resize(size_t(nR) + nRef);
  R.dataSt.resize(nRef);
  R.dataFace.assign(nRef, -1);
  TdmNormalEquations ne;
  for (auto& v : ne.val) v.resize(pat.P.nonZeros());
  ne.rhs.resize(3 * nV);
  IterateChoice ch;
  ch.best = X;
  ch.kept = X;
  std::vector<Vec3> ctrl(nV);
  for (int it = 0; it <= p.maxIterations; ++it) {
    auto tp = Clock::now();
    for (int v = 0; v < nV; ++v) ctrl[v] = X.row(v).transpose();
    long misses = 0;
    const SquaredSum s =
        ProjectFixedRows(ctrl, rows, rowFace, rowWeight, nS, scene, refN, maxDist, p.sampleWeight, R.cons, misses);
    const SquaredSum d = FootPointRows(ls, ctrl, ref, p, dataStride, maxDist, nR, R);
    res.secondsProject += Since(tp);
    const double sRms = std::sqrt(s.sum / std::max(s.count, 1.0));
    const double dRms = std::sqrt(d.sum / std::max(d.count, 1.0));
    const double dataW = p.dataWeight * dataStride;
    const double obj = std::sqrt((p.sampleWeight * s.sum + dataW * d.sum) /
                                 std::max(p.sampleWeight * s.count + dataW * d.count, 1e-300));
    res.rayMissFraction = double(misses) / std::max(nS, 1);
    if (it == 0 && res.rayMissFraction > p.maxMissFraction)
      return "the control mesh is far from the reference: " +
             std::to_string(int(std::round(100 * res.rayMissFraction))) +
             "% of the limit samples find no reference surface along their normal within " +
             std::to_string(p.maxProjectionPercent) + "% of the bbox diagonal";
    res.rmsPerIteration.push_back(sRms);
    res.dataRmsPerIteration.push_back(dRms);
    res.objectivePerIteration.push_back(obj);
    const Step step = ChooseStep(ch, obj, dRms, it, p, X, res);
    if (step == Step::Retry) continue;
    if (step == Step::Stop) break;
    prog(20 + 80.0 * (it + 1) / (p.maxIterations + 1), "Fit: project and solve");

    auto ts = Clock::now();
    Assemble(pat, R, rowFace, nR, nV, p.tangentWeight, ne);
    const double lambda = FillSystem(pat, p, ch.dampingScale, nV, ne, H);
    for (int c = 0; c < 3; ++c) ne.rhs.segment(c * nV, nV) += lambda * X.col(c);
    Eigen::VectorXd sol;
    if (!Solve(H, ne.rhs, X, reuse, factored, solver, sol, res)) { res.secondsSolve += Since(ts); break; }
    res.secondsSolve += Since(ts);
    ++res.iterations;
    if (!sol.allFinite()) break;
    for (int c = 0; c < 3; ++c) X.col(c) = sol.segment(c * nV, nV);
  }
  X = p.keepLowestDataRms ? ch.kept : ch.best;
  if (!p.keepLowestDataRms) res.keptIteration = ch.bestIteration;
  return "";
}

}  // namespace fitdetail
}  // namespace vcgext
