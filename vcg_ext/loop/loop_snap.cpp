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
  double tol;
  int iters = 0;
  int moves = 0;
};

/// Newton inside one face with boundary exit; returns 0 converged, 1 moved to neighbour via
/// edge `edge`, 2 stuck on a mesh boundary / stalled.
int NewtonInFace(Local& L, int f, double& v, double& w, int& exitEdge, int maxIt) {
  for (int it = 0; it < maxIt; ++it, ++L.iters) {
    LoopEval e;
    L.s.Evaluate(f, v, w, e, 2);
    Vec3 r = e.P - L.p;
    double g0 = e.Dv.dot(r), g1 = e.Dw.dot(r);
    double n0 = e.Dv.norm(), n1 = e.Dw.norm();
    if (std::abs(g0) <= L.tol * n0 && std::abs(g1) <= L.tol * n1) return 0;
    double H00 = e.Dv.dot(e.Dv) + e.Dvv.dot(r), H01 = e.Dv.dot(e.Dw) + e.Dvw.dot(r), H11 = e.Dw.dot(e.Dw) + e.Dww.dot(r);
    double det = H00 * H11 - H01 * H01;
    if (!(det > 0 && H00 > 0)) {  // not a local minimum model: Gauss-Newton
      H00 = e.Dv.dot(e.Dv); H01 = e.Dv.dot(e.Dw); H11 = e.Dw.dot(e.Dw);
      det = H00 * H11 - H01 * H01;
      if (!(det > 0)) return 2;
    }
    double dv = -(H11 * g0 - H01 * g1) / det, dw = -(-H01 * g0 + H00 * g1) / det;
    // backtracking on |r|^2 (only inside the face)
    double f0 = r.squaredNorm(), t = 1.0;
    double nv = v + dv, nw = w + dw;
    bool inside = nv >= 0 && nw >= 0 && nv + nw <= 1;
    if (inside) {
      for (int ls = 0; ls < 20; ++ls) {
        Vec3 q = L.s.Position(f, v + t * dv, w + t * dw);
        if ((q - L.p).squaredNorm() <= f0 * (1 + 1e-15)) break;
        t *= 0.5;
      }
      v += t * dv;
      w += t * dw;
      if (t < 1e-6) return 2;
      continue;
    }
    // leaving the face: stop on the boundary, pick the most negative barycentric
    double b[3] = {1 - nv - nw, nv, nw};
    int imin = 0;
    for (int i = 1; i < 3; ++i)
      if (b[i] < b[imin]) imin = i;
    // fraction of the step to reach the boundary of that barycentric
    double b0[3] = {1 - v - w, v, w};
    double db = b[imin] - b0[imin];
    double frac = db < 0 ? std::clamp(b0[imin] / -db, 0.0, 1.0) : 0.0;
    v += frac * dv;
    w += frac * dw;
    double bb[3] = {1 - v - w, v, w};
    bb[imin] = 0;
    for (int i = 0; i < 3; ++i) bb[i] = std::max(0.0, bb[i]);
    double sum = bb[0] + bb[1] + bb[2];
    v = bb[1] / sum;
    w = bb[2] / sum;
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
    s = ns;
  }
  toVW(s, v, w);
  return false;
}

}  // namespace

LoopSnapResult SnapToLoopSurface(const LoopSurface& surf, const Vec3& p, const EmbreeScene* netScene, int face,
                                 double v, double w, const LoopSnapParams& sp) {
  LoopSnapResult res;
  if (!surf.Ok() || surf.NumFaces() == 0 || !p.allFinite()) return res;
  const double diag = surf.NetDiagonal();
  Local L{surf, p, sp.relTol * diag};
  if (face < 0 || face >= surf.NumFaces()) {
    // start at the closest point of the control net
    bool found = false;
    if (netScene && netScene->Ok()) {
      auto h = netScene->ClosestPoint(p);
      if (h.valid) { face = h.face; v = h.u; w = h.v; found = true; }
    }
    if (!found) {
      double best = std::numeric_limits<double>::infinity();
      const auto& N = surf.Net();
      for (int f = 0; f < surf.NumFaces(); ++f) {
        double a, b;
        Vec3 q = ClosestPointOnTriangle(p, N.V[N.F[f][0]], N.V[N.F[f][1]], N.V[N.F[f][2]], &a, &b);
        double d = (q - p).squaredNorm();
        if (d < best) { best = d; face = f; v = a; w = b; }
      }
    }
  }
  double vv = v, ww = w;
  if (vv < 0) vv = 0;
  if (ww < 0) ww = 0;
  if (vv + ww > 1) { double s = vv + ww; vv /= s; ww /= s; }
  int f = face, prevFace = -1, prevEdgeFace = -1;
  bool done = false;
  int exitEdge = -1;
  for (int round = 0; round < 4 * sp.maxIterations && L.iters < sp.maxIterations * 3; ++round) {
    int st = NewtonInFace(L, f, vv, ww, exitEdge, sp.maxIterations);
    if (st == 0) { done = true; break; }
    if (st == 2) break;
    // moving out through exitEdge
    int g = surf.FaceAcross(f, exitEdge);
    if (g < 0 || g == prevFace) {
      // boundary, or ping-pong across the edge: the optimum lies on the edge
      done = EdgeMinimize(L, f, vv, ww, exitEdge, sp.maxIterations);
      if (done) {
        // accept only if the unconstrained step on the other side also points back
        break;
      }
      break;
    }
    prevEdgeFace = f;
    prevFace = f;
    CrossEdge(surf, f, vv, ww, exitEdge);
    ++L.moves;
    if (L.moves > 200) break;
  }
  (void)prevEdgeFace;
  auto finish = [&](int ff, double a, double b) {
    LoopEval e;
    surf.Evaluate(ff, a, b, e, 1);
    res.face = ff;
    res.v = a;
    res.w = b;
    res.point = e.P;
    res.normal = e.N;
    res.distance = (e.P - p).norm();
  };
  finish(f, vv, ww);
  res.converged = done;
  if (!done) {
    // Fallback: local search over the faces around the current one, each from its centroid
    // and from the current point's closest corner, keeping the best optimum found.
    res.usedFallback = true;
    const auto& N = surf.Net();
    std::vector<int> cand;
    (void)N;
    // faces within two edge-steps of the current face
    cand.push_back(f);
    for (int r = 0; r < 2; ++r) {
      size_t n0 = cand.size();
      for (size_t i = 0; i < n0; ++i)
        for (int k = 0; k < 3; ++k) {
          int g = surf.FaceAcross(cand[i], k);
          if (g >= 0 && std::find(cand.begin(), cand.end(), g) == cand.end()) cand.push_back(g);
        }
    }
    for (int g : cand) {
      double a = 1.0 / 3, b = 1.0 / 3;
      int ee;
      int st = NewtonInFace(L, g, a, b, ee, sp.maxIterations);
      bool ok = st == 0;
      if (st == 1) ok = EdgeMinimize(L, g, a, b, ee, sp.maxIterations);
      Vec3 q = surf.Position(g, a, b);
      double d = (q - p).norm();
      if (d < res.distance - 1e-15 * diag || (ok && !res.converged && d <= res.distance + 1e-15 * diag)) {
        finish(g, a, b);
        res.converged = ok;
      }
    }
  }
  res.iterations = L.iters;
  res.faceMoves = L.moves;
  return res;
}

}  // namespace vcgext
