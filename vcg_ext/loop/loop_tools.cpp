/// \file loop_tools.cpp
/// Interpolation (§3.3), per-vertex curvature, refinement mesher (§4).
#include "vcg_ext/loop/loop_tools.h"

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <unordered_set>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/memory.h"
#include "vcg_ext/core/progress.h"

namespace vcgext {

std::vector<std::pair<int, int>> HardEdgeList(const LoopSurface& s) {
  std::vector<std::pair<int, int>> out;
  for (int f = 0; f < s.NumFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      int g = s.FaceAcross(f, k);
      if (s.EdgeHard(f, k) && (g < 0 || f < g)) out.push_back({s.Net().F[f][k], s.Net().F[f][(k + 1) % 3]});
    }
  return out;
}

// ---------------------------------------------------------------------------------- interpolation
LoopInterpolateResult InterpolateLoopNet(const TriData& net, const LoopInterpolateParams& p) {
  auto t0 = std::chrono::steady_clock::now();
  LoopInterpolateResult r;
  LoopSurface s0(net, p.surface);
  if (!s0.Ok()) { r.error = s0.Error(); return r; }
  const int n = s0.NumVertices();
  std::vector<int> ri, ci;
  std::vector<double> wi;
  s0.LimitMatrixTriplets(ri, ci, wi);
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(ri.size());
  for (size_t t = 0; t < ri.size(); ++t) trip.emplace_back(ri[t], ci[t], wi[t]);
  Eigen::SparseMatrix<double> S(n, n);
  S.setFromTriplets(trip.begin(), trip.end());
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::DiagonalPreconditioner<double>> solver;
  solver.setTolerance(p.solverTol);
  solver.setMaxIterations(p.maxIterations);
  solver.compute(S);
  Eigen::MatrixXd B(n, 3), X(n, 3);
  for (int i = 0; i < n; ++i) B.row(i) = net.V[i].transpose();
  for (int d = 0; d < 3; ++d) {
    Eigen::VectorXd x = solver.solveWithGuess(B.col(d), B.col(d));
    r.iterations = std::max(r.iterations, int(solver.iterations()));
    X.col(d) = x;
  }
  Eigen::MatrixXd R = S * X - B;
  const double diag = BBoxDiagonal(net.V);
  r.residual = R.cwiseAbs().maxCoeff() / diag;
  if (!X.allFinite()) { r.error = "the interpolation solve diverged (non-finite control points)"; return r; }
  r.X.resize(n);
  for (int i = 0; i < n; ++i) r.X[i] = X.row(i).transpose();
  // cusp detection (Fig. 10)
  TriData moved = net;
  moved.V = r.X;
  LoopSurfaceParams sp = p.surface;
  sp.creaseAngleDeg = 0;
  sp.extraHardEdges = HardEdgeList(s0);
  LoopSurface s1(moved, sp);
  if (!s1.Ok()) { r.error = "interpolated net: " + s1.Error(); return r; }
  std::vector<Vec3> fn = FaceNormals(net);
  std::vector<char> flipped(n, 0), folded(net.F.size(), 0);
  const double d = p.cuspProbe;
  // Each face is probed on a barycentric lattice of order L (corners replaced by the probes at
  // `cuspProbe`): a fold of the limit surface (Fig. 10) reverses its normal in a band that can be
  // narrower than a face, so the centroid alone misses most of them.
  const int L = std::max(1, p.cuspLattice);
#pragma omp parallel for schedule(dynamic, 64)
  for (int f = 0; f < int(net.F.size()); ++f) {
    LoopEval e;
    for (int a = 0; a <= L && !folded[f]; ++a)
      for (int b = 0; a + b <= L; ++b) {
        if ((a == 0 && b == 0) || a == L || b == L) continue;  // corners: probed below
        s1.Evaluate(f, double(a) / L, double(b) / L, e, 1);
        if (e.N.dot(fn[f]) < 0) { folded[f] = 1; break; }
      }
    const double pv[3][2] = {{d, d}, {1 - 2 * d, d}, {d, 1 - 2 * d}};
    for (int k = 0; k < 3; ++k) {
      s1.Evaluate(f, pv[k][0], pv[k][1], e, 1);
      if (e.N.dot(fn[f]) < 0) { flipped[net.F[f][k]] = 1; folded[f] = 1; }  // benign race: only ever set to 1
    }
  }
  for (int i = 0; i < n; ++i)
    if (flipped[i]) { ++r.flippedVertices; r.cuspVertices.push_back(i); }
  for (int f = 0; f < int(folded.size()); ++f)
    if (folded[f]) { ++r.foldedFaces; r.foldedFaceList.push_back(f); }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// ---------------------------------------------------------------------------------- curvature
static double Pick(const LoopCurvature& k, LoopCurvatureKind kind) {
  switch (kind) {
    case LoopCurvatureKind::Mean: return k.Mean();
    case LoopCurvatureKind::Gauss: return k.Gauss();
    case LoopCurvatureKind::MaxAbs: return k.MaxAbs();
    case LoopCurvatureKind::Min: return k.k2;
    case LoopCurvatureKind::Max: return k.k1;
  }
  return 0;
}

std::vector<double> LoopVertexCurvature(const LoopSurface& s, LoopCurvatureKind kind, double probe) {
  const int n = s.NumVertices();
  std::vector<double> out(n, 0.0);
  if (!s.Ok()) return out;
  Adjacency vf = VertexFaceAdjacency(s.Net().F, n);
  const auto& F = s.Net().F;
#pragma omp parallel for schedule(dynamic, 256)
  for (int i = 0; i < n; ++i) {
    if (vf.Count(i) == 0) continue;
    bool regular = s.VertexType(i) == LoopVertexType::Smooth && vf.Count(i) == 6;
    for (const int* f = vf.Begin(i); f != vf.End(i) && regular; ++f) regular = s.FaceIsRegular(*f);
    auto corner = [&](int f) { for (int k = 0; k < 3; ++k) if (F[f][k] == i) return k; return 0; };
    if (regular) {
      int f = *vf.Begin(i), k = corner(f);
      const double cv[3][2] = {{0, 0}, {1, 0}, {0, 1}};
      out[i] = Pick(s.Curvature(f, cv[k][0], cv[k][1]), kind);
      continue;
    }
    LoopCurvature acc;
    acc.k1 = acc.k2 = 0;
    int cnt = 0;
    for (const int* f = vf.Begin(i); f != vf.End(i); ++f) {
      int k = corner(*f);
      double b[3] = {probe, probe, probe};
      b[k] = 1 - 2 * probe;
      LoopCurvature c = s.Curvature(*f, b[1], b[2]);
      acc.k1 += c.k1;
      acc.k2 += c.k2;
      ++cnt;
    }
    acc.k1 /= cnt;
    acc.k2 /= cnt;
    out[i] = Pick(acc, kind);
  }
  return out;
}

// ---------------------------------------------------------------------------------- refinement
namespace {

struct Refiner {
  const LoopSurface& s;
  const TriData& net;
  std::vector<Vec3> P;
  std::vector<int> pf;
  std::vector<double> pv, pw;
  std::vector<Tri> F;
  std::vector<std::array<int, 3>> opp;
  std::vector<std::array<unsigned char, 3>> hard;
  std::unordered_set<uint64_t> edges;
  EmbreeScene netScene;  ///< the control net: where a snap starts (see Average)

  explicit Refiner(const LoopSurface& surf) : s(surf), net(surf.Net()), netScene(surf.Net()) {}

  static uint64_t Key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
  }
  /// Expresses vertex x's parameter in control face T (possible when it lies in T's closure).
  bool Express(int x, int T, double& v, double& w) const {
    if (pf[x] == T) { v = pv[x]; w = pw[x]; return true; }
    const Tri& A = net.F[pf[x]];
    const Tri& B = net.F[T];
    double b[3] = {1 - pv[x] - pw[x], pv[x], pw[x]}, bt[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      if (b[i] <= 1e-13) continue;
      int j = 0;
      while (j < 3 && B[j] != A[i]) ++j;
      if (j == 3) return false;
      bt[j] = b[i];
    }
    double sum = bt[0] + bt[1] + bt[2];
    v = bt[1] / sum;
    w = bt[2] / sum;
    return true;
  }
  /// Parameter of the average of the given vertices (centroid / edge midpoint) if they share a
  /// control face; otherwise the closest surface point to their 3-D average (snap).
  void Average(const int* vs, int nvs, int& face, double& v, double& w) const {
    int cands[6], nc = 0;
    for (int i = 0; i < nvs; ++i) {
      cands[nc++] = pf[vs[i]];
      if (nvs == 2)
        for (int k = 0; k < 3 && nc < 6; ++k) {
          int g = s.FaceAcross(pf[vs[i]], k);
          if (g >= 0) cands[nc++] = g;
        }
    }
    for (int c = 0; c < nc; ++c) {
      double sv = 0, sw = 0;
      bool ok = true;
      for (int i = 0; i < nvs && ok; ++i) {
        double a, b;
        ok = Express(vs[i], cands[c], a, b);
        sv += a;
        sw += b;
      }
      if (ok) { face = cands[c]; v = sv / nvs; w = sw / nvs; return; }
    }
    Vec3 c = Vec3::Zero();
    for (int i = 0; i < nvs; ++i) c += P[vs[i]];
    c /= nvs;
    // Start at the control net's closest point, not at a corner's face: round a vertex of high
    // valence the corners can lie many sliver faces apart, and Newton would walk across each
    // (poles of valence 500: ~300 evaluations per snap, each subdividing the whole ring).
    LoopSnapResult r = SnapToLoopSurface(s, c, &netScene, -1, 0, 0);
    face = r.face;
    v = r.v;
    w = r.w;
  }
  void SetOpp(int g, int a, int b, int nf) {  // in face g, edge (a,b) either direction -> nf
    if (g < 0) return;
    for (int k = 0; k < 3; ++k) {
      int x = F[g][k], y = F[g][(k + 1) % 3];
      if ((x == a && y == b) || (x == b && y == a)) { opp[g][k] = nf; return; }
    }
  }
  int AddVertex(const Vec3& p, int f, double v, double w) {
    P.push_back(p);
    pf.push_back(f);
    pv.push_back(v);
    pw.push_back(w);
    return int(P.size()) - 1;
  }
  void SplitFace(int f, int p) {
    int a = F[f][0], b = F[f][1], c = F[f][2];
    int nA = opp[f][0], nB = opp[f][1], nC = opp[f][2];
    auto h = hard[f];
    int f2 = int(F.size()), f3 = f2 + 1;
    F[f] = {a, b, p};
    opp[f] = {nA, f2, f3};
    hard[f] = {h[0], 0, 0};
    F.push_back({b, c, p});
    opp.push_back({nB, f3, f});
    hard.push_back({h[1], 0, 0});
    F.push_back({c, a, p});
    opp.push_back({nC, f, f2});
    hard.push_back({h[2], 0, 0});
    SetOpp(nB, b, c, f2);
    SetOpp(nC, c, a, f3);
    edges.insert(Key(a, p));
    edges.insert(Key(b, p));
    edges.insert(Key(c, p));
  }
  void SplitEdge(int f, int k, int m) {
    int a = F[f][k], b = F[f][(k + 1) % 3], c = F[f][(k + 2) % 3];
    int g = opp[f][k];
    unsigned char hk = hard[f][k];
    int fbc = opp[f][(k + 1) % 3], fca = opp[f][(k + 2) % 3];
    unsigned char hbc = hard[f][(k + 1) % 3], hca = hard[f][(k + 2) % 3];
    int f2 = int(F.size());
    int g2 = g >= 0 ? f2 + 1 : -1;
    int j = 0, d = -1, gdb = -1, gad = -1;
    unsigned char hdb = 0, had = 0;
    if (g >= 0) {
      while (!(F[g][j] == b && F[g][(j + 1) % 3] == a)) ++j;
      d = F[g][(j + 2) % 3];
      gad = opp[g][(j + 1) % 3];  // edge (a, d)
      gdb = opp[g][(j + 2) % 3];  // edge (d, b)
      had = hard[g][(j + 1) % 3];
      hdb = hard[g][(j + 2) % 3];
    }
    F[f] = {a, m, c};
    opp[f] = {g2, f2, fca};
    hard[f] = {hk, 0, hca};
    F.push_back({m, b, c});
    opp.push_back({g, fbc, f});
    hard.push_back({hk, hbc, 0});
    SetOpp(fbc, b, c, f2);
    edges.erase(Key(a, b));
    edges.insert(Key(a, m));
    edges.insert(Key(m, b));
    edges.insert(Key(m, c));
    if (g >= 0) {
      F[g] = {b, m, d};
      opp[g] = {f2, g2, gdb};
      hard[g] = {hk, 0, hdb};
      F.push_back({m, a, d});
      opp.push_back({f, gad, g});
      hard.push_back({hk, had, 0});
      SetOpp(gad, a, d, g2);
      edges.insert(Key(m, d));
    }
  }
  /// Largest cosine of the three angles (monotone in the smallest angle, no atan2).
  static double MaxCos(const Vec3& a, const Vec3& b, const Vec3& c) {
    Vec3 ab = b - a, bc = c - b, ca = a - c;
    double lab = ab.norm(), lbc = bc.norm(), lca = ca.norm();
    if (!(lab > 0 && lbc > 0 && lca > 0)) return 1.0;
    double ca_ = -ab.dot(ca) / (lab * lca), cb = -ab.dot(bc) / (lab * lbc), cc = -bc.dot(ca) / (lbc * lca);
    return std::max(ca_, std::max(cb, cc));
  }
  std::vector<char> dirty;       // per face: centroid data must be recomputed
  std::vector<int> touched;      // faces changed since the last swap round
  void Touch(int f) {
    if (f < 0) return;
    if (int(dirty.size()) <= f) dirty.resize(F.size(), 1);
    if (!dirty[f]) { dirty[f] = 1; }
    touched.push_back(f);
  }
  /// Max-min angle swaps of the edges of the given faces; returns the faces changed.
  int SwapFaces(const std::vector<int>& cand, std::vector<int>& changed) {
    int swaps = 0;
    for (int f : cand)
      for (int k = 0; k < 3; ++k) {
        int g = opp[f][k];
        if (g < 0 || hard[f][k]) continue;
        int a = F[f][k], b = F[f][(k + 1) % 3], c = F[f][(k + 2) % 3];
        int j = 0;
        while (j < 3 && !(F[g][j] == b && F[g][(j + 1) % 3] == a)) ++j;
        if (j == 3) continue;
        int d = F[g][(j + 2) % 3];
        if (c == d) continue;
        const Vec3 &A = P[a], &B = P[b], &C = P[c], &D = P[d];
        double before = std::max(MaxCos(A, B, C), MaxCos(B, A, D));
        double after = std::max(MaxCos(C, A, D), MaxCos(D, B, C));
        if (after >= before - 1e-9) continue;
        Vec3 n0 = (B - A).cross(C - A) + (A - B).cross(D - B);
        Vec3 n1 = (A - C).cross(D - C), n2 = (B - D).cross(C - D);
        if (n1.dot(n0) <= 0 || n2.dot(n0) <= 0 || n1.dot(n2) <= 0.1 * n1.norm() * n2.norm()) continue;
        if (edges.count(Key(c, d))) continue;
        int fbc = opp[f][(k + 1) % 3], fca = opp[f][(k + 2) % 3];
        unsigned char hbc = hard[f][(k + 1) % 3], hca = hard[f][(k + 2) % 3];
        int gad = opp[g][(j + 1) % 3], gdb = opp[g][(j + 2) % 3];
        unsigned char had = hard[g][(j + 1) % 3], hdb = hard[g][(j + 2) % 3];
        F[f] = {c, a, d};
        opp[f] = {fca, gad, g};
        hard[f] = {hca, had, 0};
        F[g] = {d, b, c};
        opp[g] = {gdb, fbc, f};
        hard[g] = {hdb, hbc, 0};
        SetOpp(gad, a, d, f);
        SetOpp(fbc, b, c, g);
        edges.erase(Key(a, b));
        edges.insert(Key(c, d));
        dirty[f] = dirty[g] = 1;
        changed.push_back(f);
        changed.push_back(g);
        ++swaps;
        break;  // face f changed: move on
      }
    return swaps;
  }
};

// Per-face centroid data of the refiner, kept between passes and recomputed for changed faces.
struct CentroidData {
  std::vector<double> metric;   ///< refinement metric
  std::vector<int> cf;          ///< control face of the centroid ...
  std::vector<double> cvv, cww; ///< ... and its (v, w) there
  std::vector<Vec3> cp;         ///< centroid on the limit surface
};

// Start mesh: the control net's topology with vertices at their limit positions (isolated dropped).
void StartFromControlNet(const LoopSurface& s, Refiner& R) {
  const TriData& net = s.Net();
  const int nV = s.NumVertices(), nF = s.NumFaces();
  std::vector<int> remap(nV, -1);
  const double cv[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  for (int i = 0; i < nV; ++i) {
    auto fc = s.VertexCorner(i);
    if (fc.first < 0) continue;
    remap[i] = R.AddVertex(s.Position(fc.first, cv[fc.second][0], cv[fc.second][1]), fc.first, cv[fc.second][0], cv[fc.second][1]);
  }
  R.F.resize(nF);
  R.opp.resize(nF);
  R.hard.resize(nF);
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) {
      R.F[f][k] = remap[net.F[f][k]];
      R.opp[f][k] = s.FaceAcross(f, k);
      R.hard[f][k] = s.EdgeHard(f, k) ? 1 : 0;
      R.edges.insert(Refiner::Key(R.F[f][k], remap[net.F[f][(k + 1) % 3]]));
    }
}

// Centroid and metric of face f (area / diag^2, or (max|k| + flatWeight / diag) * area / diag).
void UpdateCentroid(const LoopSurface& s, const LoopRefineParams& p, double diag, const Refiner& R, int f,
                    CentroidData& cd) {
  const bool adaptive = p.mode == LoopRefineParams::Mode::Adaptive;
  const Tri& t = R.F[f];
  double area = 0.5 * (R.P[t[1]] - R.P[t[0]]).cross(R.P[t[2]] - R.P[t[0]]).norm();
  int face;
  double v, w;
  R.Average(t.data(), 3, face, v, w);
  LoopEval e;
  s.Evaluate(face, v, w, e, adaptive ? 2 : 0);
  cd.cf[f] = face;
  cd.cvv[f] = v;
  cd.cww[f] = w;
  cd.cp[f] = e.P;
  if (adaptive) {
    if (e.N.squaredNorm() == 0) e.N = (R.P[t[1]] - R.P[t[0]]).cross(R.P[t[2]] - R.P[t[0]]).normalized();
    LoopCurvature k = CurvatureFromDerivatives(e);
    cd.metric[f] = (k.MaxAbs() + p.flatWeight / diag) * area / diag;
  } else {
    cd.metric[f] = area / (diag * diag);
  }
}

// Recomputes the centroid data of the dirty faces (OpenMP) after growing it to the face count.
void UpdateCentroids(const LoopSurface& s, const LoopRefineParams& p, double diag, Refiner& R, CentroidData& cd,
                     std::vector<int>& todo) {
  const int m = int(R.F.size());
  cd.metric.resize(m, 0);
  cd.cf.resize(m, -1);
  cd.cvv.resize(m, 0);
  cd.cww.resize(m, 0);
  cd.cp.resize(m, Vec3::Zero());
  R.dirty.resize(m, 1);
  todo.clear();
  for (int f = 0; f < m; ++f)
    if (R.dirty[f]) { todo.push_back(f); R.dirty[f] = 0; }
#pragma omp parallel for schedule(dynamic, 256)
  for (int i = 0; i < int(todo.size()); ++i) UpdateCentroid(s, p, diag, R, todo[i], cd);
}

// The faces to split this pass: the K largest metrics first in `order` (above the tolerance); returns K.
int SelectFaces(const LoopRefineParams& p, const std::vector<double>& metric, int m, std::vector<int>& order) {
  int K = std::max(1, std::min(int(std::ceil(p.batchFraction * m)), (p.targetFaces - m + 1) / 2));
  order.resize(m);
  for (int i = 0; i < m; ++i) order[i] = i;
  if (K < m) std::nth_element(order.begin(), order.begin() + K, order.end(), [&](int a, int b) { return metric[a] > metric[b]; });
  if (p.tolerance > 0) {  // never split faces already below the tolerance
    int k2 = 0;
    for (int i = 0; i < K; ++i)
      if (metric[order[i]] > p.tolerance) order[k2++] = order[i];
    K = k2;
  }
  return K;
}

// Inserts the centroids of the first K faces of `order`; records their hard outer edges.
void InsertCentroids(Refiner& R, const std::vector<int>& order, int K, const CentroidData& cd,
                     std::vector<std::array<int, 3>>& hardSplit, LoopRefineResult& res) {
  for (int i = 0; i < K; ++i) {
    int f = order[i];
    const Tri t = R.F[f];
    const int f2 = int(R.F.size());
    int pidx = R.AddVertex(cd.cp[f], cd.cf[f], cd.cvv[f], cd.cww[f]);
    R.SplitFace(f, pidx);
    // SplitFace keeps the outer edge k of f at index 0 of face {f, f2, f2 + 1}[k]
    const int fk[3] = {f, f2, f2 + 1};
    for (int k = 0; k < 3; ++k)
      if (R.hard[fk[k]][0]) hardSplit.push_back({t[k], t[(k + 1) % 3], fk[k]});
    R.dirty.resize(R.F.size(), 1);
    R.Touch(f); R.Touch(f2); R.Touch(f2 + 1);
    ++res.insertions;
  }
}

// Splits the hard edges of refined faces at their parameter midpoint (a point of the crease curve).
void SplitHardEdges(const LoopSurface& s, Refiner& R, const std::vector<std::array<int, 3>>& hardSplit,
                    LoopRefineResult& res) {
  for (auto& e : hardSplit) {
    if (!R.edges.count(Refiner::Key(e[0], e[1]))) continue;  // already split (from the other side)
    int face = e[2];
    if (!(R.F[face][0] == e[0] && R.F[face][1] == e[1])) continue;  // cannot happen (see above)
    int vs[2] = {e[0], e[1]};
    int pfce;
    double v, w;
    R.Average(vs, 2, pfce, v, w);
    int mid = R.AddVertex(s.Position(pfce, v, w), pfce, v, w);
    int g = R.opp[face][0];
    const int nf = int(R.F.size());
    R.SplitEdge(face, 0, mid);
    R.dirty.resize(R.F.size(), 1);
    R.Touch(face); R.Touch(g);
    for (int x = nf; x < int(R.F.size()); ++x) R.Touch(x);
    ++res.edgeSplits;
  }
}

// Sorts a face list and removes duplicates.
void SortUnique(std::vector<int>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// Max-min angle swap rounds: the faces touched by this pass, then the swapped ones and their neighbours.
void SwapRounds(const LoopRefineParams& p, Refiner& R, std::vector<int>& cand, std::vector<int>& changed,
                LoopRefineResult& res) {
  cand.swap(R.touched);
  SortUnique(cand);
  for (int sp = 0; sp < p.swapPasses && !cand.empty(); ++sp) {
    changed.clear();
    int n = R.SwapFaces(cand, changed);
    res.swaps += n;
    if (n == 0) break;
    // next round: the swapped faces and their neighbours
    cand.clear();
    for (int f : changed) {
      cand.push_back(f);
      for (int k = 0; k < 3; ++k)
        if (R.opp[f][k] >= 0) cand.push_back(R.opp[f][k]);
    }
    SortUnique(cand);
  }
}

// EstimateLoopRefineMemoryMb's constant, fitted to what was measured: meshlabserver's peak resident
// memory (`/usr/bin/time`, loop_refine.mlx, adaptive, bunny00's 75k-triangle net, 2026-12-07) above
// its run to 1e5 triangles (674 MB): +210 MB at 1e6 triangles (estimate 229), +696 MB at 4e6 (916),
// +10.8 GB at 5e7 (11.2). The refiner's arrays, its result and two vcglib meshes (the filter's and
// the layer's copy) grow by doubling, so the bytes per triangle vary (160-235 between those sizes);
// 240 bounds them.
constexpr double kLoopRefineBytesPerTriangle = 240;

}  // namespace

double EstimateLoopRefineMemoryMb(long targetFaces) {
  return kLoopRefineBytesPerTriangle * double(std::max(0L, targetFaces)) / (1024.0 * 1024.0);
}

LoopRefineResult RefineLoopSurface(const LoopSurface& s, const LoopRefineParams& p, vcg::CallBackPos* cb) {
  auto t0 = std::chrono::steady_clock::now();
  LoopRefineResult res;
  if (!s.Ok()) { res.error = s.Error(); return res; }
  if (p.targetFaces < 1) { res.error = "targetFaces must be positive"; return res; }
  res.error = CheckMemory(EstimateLoopRefineMemoryMb(p.targetFaces), p.maxMemoryMb,
                          "refining to " + std::to_string(p.targetFaces) + " triangles");
  if (!res.error.empty()) {
    res.error += "; choose fewer target triangles";
    return res;
  }
  Progress prog(cb);
  Refiner R(s);
  StartFromControlNet(s, R);
  const double diag = s.NetDiagonal();
  CentroidData cd;
  R.dirty.assign(R.F.size(), 1);
  R.edges.reserve(size_t(p.targetFaces) * 2);
  R.P.reserve(size_t(p.targetFaces) / 2 + R.P.size() + 16);
  std::vector<int> todo, order, cand, changed;
  while (int(R.F.size()) < p.targetFaces) {
    const int m = int(R.F.size());
    UpdateCentroids(s, p, diag, R, cd, todo);
    double mx = 0;
    for (double x : cd.metric) mx = std::max(mx, x);
    res.maxMetric = mx;
    if (p.tolerance > 0 && mx <= p.tolerance) break;
    const int K = SelectFaces(p, cd.metric, m, order);
    R.touched.clear();
    std::vector<std::array<int, 3>> hardSplit;  // (a, b, face whose edge 0 is a->b)
    InsertCentroids(R, order, K, cd, hardSplit, res);
    SplitHardEdges(s, R, hardSplit, res);
    SwapRounds(p, R, cand, changed, res);
    ++res.passes;
    prog(100.0 * double(R.F.size()) / p.targetFaces, "Loop surrogate: refining");
  }
  // moved, not copied (the refiner's peak, bunny00 to 3e6 triangles: 586 -> 576 MB)
  res.mesh.V = std::move(R.P);
  res.mesh.F = std::move(R.F);
  res.paramFace = std::move(R.pf);
  res.paramV = std::move(R.pv);
  res.paramW = std::move(R.pw);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace vcgext
