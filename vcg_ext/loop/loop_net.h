#pragma once
/// \file loop_net.h
/// Internals of the Loop surface kernel (loop_surface.cpp), one concept per file:
/// - loop_patch.cpp: regular box-spline patches (§3.1) and the regularity test that gathers a
///   local net's 12 control points, with ghosts across a straight crease (§2.4);
/// - loop_local_subdivision.cpp: one step of local Loop subdivision of a net (§3.2, hard edges and
///   vertices by the 1-D spline rules) and the self-similar rings below the cache depth.
#include "vcg_ext/loop/loop_surface.h"

#include <array>
#include <string>
#include <vector>

namespace vcgext::loop_internal {

/// A regular patch as monomial coefficients G = X * phi / 12 (3 x 15, stored per monomial).
struct Patch {
  double g[15][3];
};

/// The patch's points from its 12 control points (the nodes of Fig. 6).
Patch MakePatch(const Vec3 X[12]);

/// Position and derivatives up to `order` at (v, w).
inline void EvalPatch(const Patch& p, double v, double w, int order, LoopEval& e) {
  const double v2 = v * v, w2 = w * w, vw = v * w;
  const double c[15] = {1, v, w, v2, vw, w2, v2 * v, v2 * w, v * w2, w2 * w, v2 * v2, v2 * vw, v2 * w2, vw * w2, w2 * w2};
  double P[3] = {0, 0, 0};
  for (int m = 0; m < 15; ++m)
    for (int d = 0; d < 3; ++d) P[d] += p.g[m][d] * c[m];
  e.P = Vec3(P[0], P[1], P[2]);
  if (order < 1) return;
  const double cv[15] = {0, 1, 0, 2 * v, w, 0, 3 * v2, 2 * vw, w2, 0, 4 * v2 * v, 3 * v2 * w, 2 * v * w2, w2 * w, 0};
  const double cw[15] = {0, 0, 1, 0, v, 2 * w, 0, v2, 2 * vw, 3 * w2, 0, v2 * v, 2 * v2 * w, 3 * v * w2, 4 * w2 * w};
  double A[3] = {0, 0, 0}, B[3] = {0, 0, 0};
  for (int m = 1; m < 15; ++m)
    for (int d = 0; d < 3; ++d) { A[d] += p.g[m][d] * cv[m]; B[d] += p.g[m][d] * cw[m]; }
  e.Dv = Vec3(A[0], A[1], A[2]);
  e.Dw = Vec3(B[0], B[1], B[2]);
  if (order < 2) return;
  const double cvv[15] = {0, 0, 0, 2, 0, 0, 6 * v, 2 * w, 0, 0, 12 * v2, 6 * vw, 2 * w2, 0, 0};
  const double cvw[15] = {0, 0, 0, 0, 1, 0, 0, 2 * v, 2 * w, 0, 0, 3 * v2, 4 * vw, 3 * w2, 0};
  const double cww[15] = {0, 0, 0, 0, 0, 2, 0, 0, 2 * v, 6 * w, 0, 0, 2 * v2, 6 * vw, 12 * w2};
  double C[3] = {0, 0, 0}, D[3] = {0, 0, 0}, E[3] = {0, 0, 0};
  for (int m = 3; m < 15; ++m)
    for (int d = 0; d < 3; ++d) {
      C[d] += p.g[m][d] * cvv[m];
      D[d] += p.g[m][d] * cvw[m];
      E[d] += p.g[m][d] * cww[m];
    }
  e.Dvv = Vec3(C[0], C[1], C[2]);
  e.Dvw = Vec3(D[0], D[1], D[2]);
  e.Dww = Vec3(E[0], E[1], E[2]);
}

// Local nets (§3.2): the faces incident to the three corners of a target triangle, with hard
// edge flags and vertex types. Subdividing a net yields the net of any of the 4 sub-triangles.
struct LNet {
  std::vector<Vec3> P;
  std::vector<unsigned char> type;  // LoopVertexType
  std::vector<Tri> F;
  std::vector<std::array<unsigned char, 3>> H;  // edge F[f][k] -> F[f][(k+1)%3] hard
  int target = 0;                                // F[target] = (c0, c1, c2)
};

/// Regularity test and gathering of the 12 control points (with ghosts across a straight crease).
bool Gather(const LNet& n, Vec3 X[12]);

/// Loop's smooth-vertex weight for valence k: (5/8 - (3/8 + cos(2 pi / k) / 4)^2) / k.
double LoopBeta(int k);

/// One step of local Loop subdivision: the net of sub-triangle `child` (0..2 corner c_child, 3 middle).
LNet Subdivide(const LNet& n, int child);

/// Self-similar local net below the cache depth (Stam's observation without the eigenbasis): the
/// net of a corner sub-triangle touching the one irregular vertex has the same topology at every
/// level, so one level is a fixed linear map S (n x n) and the three other children are regular
/// tiles whose 12 control points are fixed linear maps T_c (12 x n) of the net. Depends only on
/// the topology (faces, hard flags, vertex types), so it is shared by all nets of one configuration.
struct Ring {
  int n = 0, kc = -1;              // net size, the child that stays irregular
  std::vector<double> S;           // n x n, row-major
  std::array<std::vector<double>, 4> T;  // 12 x n, row-major, for c != kc
};

/// The net's topology (faces, hard flags, vertex types) as a key for shared Rings.
std::string TopologyKey(const LNet& n);
/// Builds the Ring of a net, or returns false when the net is not self-similar.
bool BuildRing(const LNet& net, Ring& r);

}  // namespace vcgext::loop_internal
