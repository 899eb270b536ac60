/// \file loop_snap.cpp
/// Closest point on the Loop surface (§2.1): Newton on (v, w), moving to the neighbouring
/// triangle opposite the most negative barycentric; edge-constrained 1-D Newton when the
/// iterate ping-pongs across an edge (closest point on a crease); damped-descent fallback.
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/loop/loop_surface.h"

namespace vcgext {

namespace {

/// Moves a point on edge k of face f (barycentrics b) into the neighbour's parameters.
bool CrossEdge(const LoopSurface& s, int& f, double& v, double& w, int k) {
  int g = s.FaceAcross(f, k);
  if (g < 0) return false;
  const Tri& T = s.Net().F[f];
  double b[3] = {1 - v - w, v, w};
  double bg[3] = {0, 0, 0};
  const Tri& G = s.Net().F[g];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (G[j] == T[i]) bg[j] = b[i];
  f = g;
  v = bg[1];
  w = bg[2];
  return true;
}

struct Local {
  const LoopSurface& s;
  Vec3 p;
  double tol;    ///< tangential tolerance (absolute), never below the round-off of x - p
  double noise;  ///< round-off level of a coordinate difference (~ eps * coordinate magnitude)
  int iters = 0;
  int moves = 0;
};

/// Whether the tangential residual (gradient of |x - p|^2 / 2 in 3-D units) is below tolerance.
inline bool Stationary(const Local& L, const LoopEval& e, const Vec3& r) {
  double g0 = e.Dv.dot(r), g1 = e.Dw.dot(r);
  return std::abs(g0) <= L.tol * e.Dv.norm() && std::abs(g1) <= L.tol * e.Dw.norm();
}

/// Halves t (from t0, at most 30 times) until |x(v + t dv, w + t dw) - p|^2 <= bound.
double Backtrack(const Local& L, int f, double v, double w, double dv, double dw, double t0, double bound) {
  double t = t0;
  for (int ls = 0; ls < 30; ++ls) {
    if ((L.s.Position(f, v + t * dv, w + t * dw) - L.p).squaredNorm() <= bound) break;
    t *= 0.5;
  }
  return t;
}

/// The Newton step (dv, dw) in face coordinates for the residual r at evaluation e (gradient g0,
/// g1), Gauss-Newton where the Hessian is not a local minimum model, clamped to a trust region;
/// false when even Gauss-Newton is singular.
bool NewtonStep(const LoopEval& e, const Vec3& r, double g0, double g1, double& dv, double& dw) {
  double H00 = e.Dv.dot(e.Dv) + e.Dvv.dot(r), H01 = e.Dv.dot(e.Dw) + e.Dvw.dot(r), H11 = e.Dw.dot(e.Dw) + e.Dww.dot(r);
  double det = H00 * H11 - H01 * H01;
  if (!(det > 0 && H00 > 0)) {  // not a local minimum model: Gauss-Newton
    H00 = e.Dv.dot(e.Dv); H01 = e.Dv.dot(e.Dw); H11 = e.Dw.dot(e.Dw);
    det = H00 * H11 - H01 * H01;
    if (!(det > 0)) return false;
  }
  dv = -(H11 * g0 - H01 * g1) / det;
  dw = -(-H01 * g0 + H00 * g1) / det;
  // Trust region in the face's barycentric chart: far from the optimum the quadratic model is
  // poor (a full step from the centroid overshot by 2-3x near curved corners) and a long step
  // decides the face crossing on it; at most a quarter of the face per iteration.
  const double len = std::max(std::abs(dv), std::abs(dw));
  if (len > 0.25) { dv *= 0.25 / len; dw *= 0.25 / len; }
  return true;
}

/// Where the step (dv, dw) from (v, w) leaves the face: the barycentric that reaches 0 first
/// (its index, -1 if none) and the step's fraction `frac` in [0, 1] at which it does.
int FirstBarycentricToZero(double v, double w, double dv, double dw, double& frac) {
  const double nv = v + dv, nw = w + dw;
  double b0[3] = {1 - v - w, v, w}, b1[3] = {1 - nv - nw, nv, nw};
  int imin = -1;
  frac = 1.0;
  for (int i = 0; i < 3; ++i)
    if (b1[i] < 0) {
      double fi = b0[i] / (b0[i] - b1[i]);
      if (imin < 0 || fi < frac) { frac = fi; imin = i; }
    }
  frac = std::clamp(frac, 0.0, 1.0);
  return imin;
}

/// (v, w) put exactly on the face's side where barycentric `imin` is 0 (the others clamped to 0
/// and renormalised).
void OntoSide(int imin, double& v, double& w) {
  double bb[3] = {1 - v - w, v, w};
  bb[imin] = 0;
  for (int i = 0; i < 3; ++i) bb[i] = std::max(0.0, bb[i]);
  double sum = bb[0] + bb[1] + bb[2];
  v = bb[1] / sum;
  w = bb[2] / sum;
}

/// Newton inside one face with boundary exit; returns 0 converged, 1 moved to neighbour via
/// edge `edge`, 2 stuck on a mesh boundary / stalled.
int NewtonInFace(Local& L, int f, double& v, double& w, int& exitEdge, int maxIt) {
  for (int it = 0; it < maxIt; ++it, ++L.iters) {
    LoopEval e;
    L.s.Evaluate(f, v, w, e, 2);
    Vec3 r = e.P - L.p;
    double g0 = e.Dv.dot(r), g1 = e.Dw.dot(r);
    if (Stationary(L, e, r)) return 0;
    double dv, dw;
    if (!NewtonStep(e, r, g0, g1, dv, dw)) return 2;
    // A step shorter (in 3-D) than the tolerance: converged to round-off. This is what used to
    // stall: near the optimum the decrease of |r|^2 (~ tangential^2) is far below the round-off
    // of |r|^2 (~ |r| * eps * coordinates) when p is off the surface, so backtracking on |r|^2
    // rejected good steps and Newton gave up just short of the tolerance.
    double step3 = (dv * e.Dv + dw * e.Dw).norm();
    double nv = v + dv, nw = w + dw;
    bool inside = nv >= 0 && nw >= 0 && nv + nw <= 1;
    if (inside && step3 <= L.tol) { v = nv; w = nw; return 0; }
    // backtracking on |r|^2 with a round-off slack (only inside the face)
    double f0 = r.squaredNorm(), t = 1.0;
    const double slack = 4.0 * L.noise * (std::sqrt(f0) + step3);
    if (inside) {
      t = Backtrack(L, f, v, w, dv, dw, 1.0, f0 + slack);
      v += t * dv;
      w += t * dw;
      if (t * step3 <= L.tol) return 0;  // no progress possible above round-off
      if (t < 1e-9) return 2;
      continue;
    }
    // Leaving the face. The barycentric that reaches 0 first along the step decides the edge.
    double frac;
    const int imin = FirstBarycentricToZero(v, w, dv, dw, frac);
    // Cross only if |x - p|^2 still decreases along the step at the boundary: a Newton step far
    // from the optimum can overshoot an optimum that lies inside this face (near a corner, where
    // the face's (v, w) chart is strongly curved); then take a shorter step inside instead.
    {
      LoopEval eb;
      L.s.Evaluate(f, v + frac * dv, w + frac * dw, eb, 1);
      const Vec3 rb = eb.P - L.p;
      const double slope = eb.Dv.dot(rb) * dv + eb.Dw.dot(rb) * dw;
      if (slope > 0 && frac > 0) {
        const double t2 = Backtrack(L, f, v, w, dv, dw, 0.5 * frac, f0 + slack);
        v += t2 * dv;
        w += t2 * dw;
        if (t2 * step3 <= L.tol) return 0;
        continue;
      }
    }
    v += frac * dv;
    w += frac * dw;
    OntoSide(imin, v, w);
    exitEdge = (imin + 1) % 3;
    return 1;
  }
  return 2;
}

/// 1-D Newton along edge k of face f (closest point on a crease or on the surface boundary).
bool EdgeMinimize(Local& L, int f, double& v, double& w, int k, int maxIt) {
  // parameter s along the edge from corner k to corner k+1
  double b[3] = {1 - v - w, v, w};
  double s = b[(k + 1) % 3] / std::max(1e-300, b[k] + b[(k + 1) % 3]);
  auto toVW = [&](double ss, double& vv, double& ww) {
    double bb[3] = {0, 0, 0};
    bb[k] = 1 - ss;
    bb[(k + 1) % 3] = ss;
    vv = bb[1];
    ww = bb[2];
  };
  // d(v,w)/ds
  double dvds = (k == 0 ? 1 : k == 1 ? -1 : 0), dwds = (k == 0 ? 0 : k == 1 ? 1 : -1);
  for (int it = 0; it < maxIt; ++it, ++L.iters) {
    toVW(s, v, w);
    LoopEval e;
    L.s.Evaluate(f, v, w, e, 2);
    Vec3 r = e.P - L.p;
    Vec3 xs = dvds * e.Dv + dwds * e.Dw;
    Vec3 xss = dvds * dvds * e.Dvv + 2 * dvds * dwds * e.Dvw + dwds * dwds * e.Dww;
    double g = xs.dot(r), h = xs.dot(xs) + xss.dot(r);
    if (std::abs(g) <= L.tol * xs.norm()) return true;
    if (!(h > 0)) h = xs.dot(xs);
    double ns = std::clamp(s - g / h, 0.0, 1.0);
    if (ns == s) return true;  // at an edge end (a corner): constrained optimum
    if (std::abs(ns - s) * xs.norm() <= L.tol) { s = ns; toVW(s, v, w); return true; }
    s = ns;
  }
  toVW(s, v, w);
  return false;
}

/// Whether a point on edge k of face f (found by EdgeMinimize) is a true closest point: on a
/// smooth edge the 2-D gradient must vanish; on a hard or boundary edge the descent direction
/// must leave face f through that edge (the crease/boundary is the constrained optimum; the
/// caller reaches this only after the other side pointed back, or at a boundary).
bool EdgeOptimal(const Local& L, int f, double v, double w, int k) {
  LoopEval e;
  L.s.Evaluate(f, v, w, e, 1);
  Vec3 r = e.P - L.p;
  if (Stationary(L, e, r)) return true;
  if (!L.s.EdgeHard(f, k) && L.s.FaceAcross(f, k) >= 0) return false;
  // descent direction in (v, w): -(G^-1) grad; leaving through edge k lowers barycentric (k+2)%3
  double E = e.Dv.dot(e.Dv), F = e.Dv.dot(e.Dw), G = e.Dw.dot(e.Dw), det = E * G - F * F;
  if (!(det > 0)) return false;
  double g0 = e.Dv.dot(r), g1 = e.Dw.dot(r);
  double dv = -(G * g0 - F * g1) / det, dw = -(-F * g0 + E * g1) / det;
  double db[3] = {-dv - dw, dv, dw};
  return db[(k + 2) % 3] < 0;
}


// The face and barycentrics (v, w) of the control net's closest point to p (the walk's start).
void ClosestNetPoint(const LoopSurface& surf, const Vec3& p, const EmbreeScene* netScene, int& face, double& v,
                     double& w) {
  if (netScene && netScene->Ok()) {
    auto h = netScene->ClosestPoint(p);
    if (h.valid) { face = h.face; v = h.u; w = h.v; return; }
  }
  double best = std::numeric_limits<double>::infinity();
  const auto& N = surf.Net();
  for (int f = 0; f < surf.NumFaces(); ++f) {
    double a, b;
    Vec3 q = ClosestPointOnTriangle(p, N.V[N.F[f][0]], N.V[N.F[f][1]], N.V[N.F[f][2]], &a, &b);
    double d = (q - p).squaredNorm();
    if (d < best) { best = d; face = f; v = a; w = b; }
  }
}

// Newton in face f from (vv, ww), crossing to the neighbour wherever the step leaves the face,
// until a stationary point (true), the boundary or a ping-pong (the optimum on that edge), or the
// iteration and move limits. On return (f, vv, ww) is where the walk ended.
bool WalkToOptimum(Local& L, int& f, double& vv, double& ww, const LoopSnapParams& sp) {
  const LoopSurface& surf = L.s;
  int prevFace = -1, returns = 0, exitEdge = -1;
  for (int round = 0; round < 4 * sp.maxIterations && L.iters < sp.maxIterations * 3; ++round) {
    int st = NewtonInFace(L, f, vv, ww, exitEdge, sp.maxIterations);
    if (st == 0) return true;
    if (st == 2) return false;
    // moving out through exitEdge
    int g = surf.FaceAcross(f, exitEdge);
    // Going back to the face we came from: a ping-pong across their edge (the optimum lies on
    // it) only when it repeats. A single return is legitimate: a long step near a corner can
    // overshoot into the neighbour, whose step points back (elephant.off); the second visit
    // starts from the edge, where the model is good.
    const bool pingPong = g == prevFace && ++returns > 2;
    if (g < 0 || pingPong)  // boundary, or ping-pong across the edge: the optimum lies on the edge
      return EdgeMinimize(L, f, vv, ww, exitEdge, sp.maxIterations) && EdgeOptimal(L, f, vv, ww, exitEdge);
    prevFace = f;
    CrossEdge(surf, f, vv, ww, exitEdge);
    ++L.moves;
    if (L.moves > 200) return false;
  }
  return false;
}

// The fallback's candidate faces: f first, then the faces within two edge-steps of f and every
// face around its three corners, cut to the kMaxFallbackFaces closest to p.
std::vector<int> FallbackFaces(const LoopSurface& surf, const Vec3& p, int f) {
  const auto& N = surf.Net();
  std::vector<int> cand;
  // faces within two edge-steps of the current face ...
  auto add = [&](int g) {
    if (g >= 0 && std::find(cand.begin(), cand.end(), g) == cand.end()) cand.push_back(g);
  };
  cand.push_back(f);
  for (int r = 0; r < 2; ++r) {
    size_t n0 = cand.size();
    for (size_t i = 0; i < n0; ++i)
      for (int k = 0; k < 3; ++k) add(surf.FaceAcross(cand[i], k));
  }
  // ... and every face around its three corners: near a high-valence vertex the closest point
  // can be several edge-steps away, and Newton ping-pongs between two faces of the fan (the
  // (v, w) charts meet at an angle there). Found on elephant.off: 14 of 396 points on the
  // surface re-snapped to 1e-4..1e-3 of the diagonal.
  for (int k = 0; k < 3; ++k) {
    const int x = N.F[f][k];
    std::vector<int> fan{f};
    for (size_t i = 0; i < fan.size(); ++i)
      for (int e = 0; e < 3; ++e) {
        int g = surf.FaceAcross(fan[i], e);
        if (g < 0 || std::find(fan.begin(), fan.end(), g) != fan.end()) continue;
        const auto& G = N.F[g];
        if (G[0] == x || G[1] == x || G[2] == x) fan.push_back(g);
      }
    for (int g : fan) add(g);
  }
  // Round a vertex of very high valence (a UV sphere's pole of valence 500) the fans hold
  // hundreds of faces, each a Newton solve whose evaluations subdivide the whole ring: keep the
  // current face and the kMaxFallbackFaces - 1 others whose control triangles are closest to p
  // (the closest limit point lies over them: the limit surface stays within the control
  // polygon's convex hull). Ordinary meshes have fewer candidates and are searched in full.
  constexpr size_t kMaxFallbackFaces = 48;
  if (cand.size() > kMaxFallbackFaces) {
    std::vector<std::pair<double, int>> byDistance;
    byDistance.reserve(cand.size() - 1);
    for (size_t i = 1; i < cand.size(); ++i) {
      const auto& G = N.F[cand[i]];
      const Vec3 q = ClosestPointOnTriangle(p, N.V[G[0]], N.V[G[1]], N.V[G[2]], nullptr, nullptr);
      byDistance.push_back({(q - p).squaredNorm(), cand[i]});
    }
    std::stable_sort(byDistance.begin(), byDistance.end(),
                     [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a.first < b.first; });
    cand.resize(1);
    for (size_t i = 0; i + 1 < kMaxFallbackFaces; ++i) cand.push_back(byDistance[i].second);
  }
  return cand;
}

// Fills res's point, frame and distance with the limit at (ff, a, b).
void SetSnapPoint(const LoopSurface& surf, const Vec3& p, int ff, double a, double b, LoopSnapResult& res) {
  LoopEval e;
  surf.Evaluate(ff, a, b, e, 1);
  res.face = ff;
  res.v = a;
  res.w = b;
  res.point = e.P;
  res.normal = e.N;
  res.distance = (e.P - p).norm();
}

// Fallback when the walk did not converge: a local search over FallbackFaces, each from its
// centroid, keeping the closest optimum found (a converged one at equal distance).
void FallbackSearch(Local& L, int f, double diag, const LoopSnapParams& sp, LoopSnapResult& res) {
  const LoopSurface& surf = L.s;
  res.usedFallback = true;
  for (int g : FallbackFaces(surf, L.p, f)) {
    double a = 1.0 / 3, b = 1.0 / 3;
    int ee;
    int st = NewtonInFace(L, g, a, b, ee, sp.maxIterations);
    bool ok = st == 0;
    if (st == 1) ok = EdgeMinimize(L, g, a, b, ee, sp.maxIterations) && EdgeOptimal(L, g, a, b, ee);
    Vec3 q = surf.Position(g, a, b);
    double d = (q - L.p).norm();
    if (d < res.distance - 1e-15 * diag || (ok && !res.converged && d <= res.distance + 1e-15 * diag)) {
      SetSnapPoint(surf, L.p, g, a, b, res);
      res.converged = ok;
    }
  }
}

}  // namespace

LoopSnapResult SnapToLoopSurface(const LoopSurface& surf, const Vec3& p, const EmbreeScene* netScene, int face,
                                 double v, double w, const LoopSnapParams& sp) {
  LoopSnapResult res;
  if (!surf.Ok() || surf.NumFaces() == 0 || !p.allFinite()) return res;
  const double diag = surf.NetDiagonal();
  const double noise = 4 * std::numeric_limits<double>::epsilon() * (p.cwiseAbs().maxCoeff() + diag);
  Local L{surf, p, std::max(sp.relTol * diag, 16 * noise), noise};
  if (face < 0 || face >= surf.NumFaces()) ClosestNetPoint(surf, p, netScene, face, v, w);
  double vv = v, ww = w;
  if (vv < 0) vv = 0;
  if (ww < 0) ww = 0;
  if (vv + ww > 1) { double s = vv + ww; vv /= s; ww /= s; }
  int f = face;
  const bool done = WalkToOptimum(L, f, vv, ww, sp);
  SetSnapPoint(surf, p, f, vv, ww, res);
  res.converged = done;
  if (!done) FallbackSearch(L, f, diag, sp, res);
  res.iterations = L.iters;
  res.faceMoves = L.moves;
  return res;
}

}  // namespace vcgext
