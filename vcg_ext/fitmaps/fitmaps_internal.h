#pragma once
/// \file fitmaps_internal.h
/// Building blocks of the Fitmaps (paper §3.1.2–3.1.3), exposed for unit tests: the tangent
/// frame, the cubic height field and its least-squares fit, the bounded "minimax" breadth-first
/// gathering of a connected neighbourhood, and the closest point on a cubic graph.
/// Not part of the public API.
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {
namespace fitmaps_internal {

/// Orthonormal frame (u, v, n) at origin o; n is the (unit) normal.
struct Frame {
  Vec3 o = Vec3::Zero(), u = Vec3::UnitX(), v = Vec3::UnitY(), n = Vec3::UnitZ();
  static Frame Make(const Vec3& origin, const Vec3& unitNormal);
  Vec3 Local(const Vec3& p) const {
    Vec3 d = p - o;
    return Vec3(d.dot(u), d.dot(v), d.dot(n));
  }
  Vec3 World(const Vec3& l) const { return o + l[0] * u + l[1] * v + l[2] * n; }
  Vec3 WorldDir(const Vec3& l) const { return l[0] * u + l[1] * v + l[2] * n; }
};

/// Cubic height field h(u,v) = sum c_k m_k(u/r, v/r) with the 10 monomials
/// 1, s, t, s^2, st, t^2, s^3, s^2 t, s t^2, t^3 of the scaled coordinates (s,t) = (u,v)/r.
struct Cubic {
  double c[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  double r = 1;  ///< scale of the coordinates
  double Eval(double u, double v) const;
  /// Value, first and second derivatives with respect to u, v (not s, t).
  void Eval2(double u, double v, double& h, double& hu, double& hv, double& huu, double& huv,
             double& hvv) const;
  /// Unit normal (-h_u, -h_v, 1)/|.| in frame coordinates.
  Vec3 Normal(double u, double v) const;
};

/// Weighted least-squares normal equations of the cubic, accumulated point by point (unscaled
/// monomials, so the same accumulator serves every radius of a nested sequence).
class CubicAccumulator {
 public:
  void Add(double u, double v, double h, double w = 1.0);
  /// Solves for the cubic at scale r. A tiny ridge term (1e-10 of the mean diagonal) keeps
  /// under-determined systems solvable (fewer than 10 points, collinear points): the result then
  /// interpolates the points with small coefficients. Returns false only if nothing was added.
  bool Solve(double r, Cubic& out) const;
  int Count() const { return n_; }

 private:
  Eigen::Matrix<double, 10, 10> A_ = Eigen::Matrix<double, 10, 10>::Zero();
  Eigen::Matrix<double, 10, 1> b_ = Eigen::Matrix<double, 10, 1>::Zero();
  int n_ = 0;
};

/// Closest point on the graph of `g` (frame coordinates) to x, by Newton's method from
/// (x_u, x_v). Returns false if it did not converge or left the disc of radius maxUV.
bool ClosestPointOnCubic(const Cubic& g, const Vec3& x, double maxUV, double& u, double& v);

/// Per-thread scratch of the bounded breadth-first traversal.
struct GatherScratch {
  std::vector<double> key;  ///< minimax key per graph vertex (inf = not reached)
  std::vector<int> touched;
  std::vector<std::pair<double, int>> heap;
  void Reset(size_t n);
};

/// Breadth-first traversal from `src` over the graph `adj` (positions X) that never steps on a
/// vertex farther than maxR from X[src] (Euclidean). Vertices are reported in increasing order of
/// key(q) = min over paths src..q of the largest distance from X[src] along the path; hence the
/// neighbourhood of radius r (the connected region a traversal stopped at distance r reaches) is
/// exactly the prefix with key <= r. Output: (vertex, key) pairs. Keys stay in `s.key` until the
/// next call (unreached or not yet popped when maxCount stopped the traversal: +inf or an upper
/// bound). At most maxCount vertices are reported (the nearest-key prefix). With `center`,
/// distances are measured from it instead of X[src] (a traversal of a coarse graph started at
/// the cluster of a mesh vertex, centred on that vertex).
void GatherMinimax(const Adjacency& adj, const std::vector<Vec3>& X, int src, double maxR,
                   GatherScratch& s, std::vector<std::pair<int, double>>& out,
                   size_t maxCount = size_t(-1), const Vec3* center = nullptr);

/// The neighbourhood of one radius only: a plain breadth-first traversal restricted to the ball
/// of radius r around `center` (default X[src]); the same vertex set as GatherMinimax's prefix
/// with key <= r, without the priority queue. Keys are the vertices' own distances (unordered).
void GatherBall(const Adjacency& adj, const std::vector<Vec3>& X, int src, double r, GatherScratch& s,
                std::vector<std::pair<int, double>>& out, const Vec3* center = nullptr);

/// Deterministic per-(seed, a, b) random stream (splitmix64).
struct Rng {
  uint64_t state;
  Rng(uint64_t seed, uint64_t a, uint64_t b);
  uint64_t Next();
  double Uniform() { return double(Next() >> 11) * (1.0 / 9007199254740992.0); }  ///< [0,1)
};

}  // namespace fitmaps_internal
}  // namespace vcgext
