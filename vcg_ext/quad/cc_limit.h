#pragma once
/// \file cc_limit.h
/// Closed-form local Catmull-Clark limit evaluation on an editable QuadMesh, cheap enough to be
/// re-evaluated after every local operation of the simplification (Fitmaps §3.2–3.4), where
/// rebuilding OpenSubdiv topology each step would be far too slow. Boundary rules are those of
/// OpenSubdiv's VTX_BOUNDARY_EDGE_ONLY (boundary edges infinitely sharp, boundary curves cubic
/// B-splines, valence-2 boundary corners smooth). Verified against OpenSubdiv in tests/quad.
#include <array>
#include <utility>
#include <vector>

#include "vcg_ext/quad/quad_mesh.h"

namespace vcgext {
namespace quad {

/// Read-only view of a QuadMesh that memoizes face centroids and edge adjacency (each computed
/// on first use). Valid only while the mesh's positions and connectivity do not change, e.g. the
/// checks of one simplification step, where every face centroid and neighbour is otherwise
/// recomputed ~10 times (edge-midpoint and face-centre stencils overlap); Reset() forgets
/// everything in O(1) and must be called after any change. Not thread-safe.
class QuadMemo {
 public:
  explicit QuadMemo(const QuadMesh& m) : m_(&m) {}
  /// Forgets all entries (and adapts to the mesh's current number of face slots).
  void Reset();
  const QuadMesh& Mesh() const { return *m_; }
  const Vec3& Centroid(int f) const;
  int AcrossEdge(int f, int k) const;
  /// Number of memoized entries that differ from a fresh computation (test mode: must be 0).
  int CountStale() const;

 private:
  void Adjacency(int f) const;
  const QuadMesh* m_;
  unsigned epoch_ = 1;
  mutable std::vector<unsigned> cStamp_, aStamp_;
  mutable std::vector<Vec3> cent_;
  mutable std::vector<std::array<int, 4>> adj_;
};

/// Limit-position mask of control vertex v as (vertex, weight) pairs (weights sum to 1):
/// interior valence n: (n^2 v + 4 sum e_j + sum f_j) / (n (n+5)) (e_j edge neighbours, f_j the
/// opposite corners of the incident faces); boundary: (v_prev + 4 v + v_next) / 6.
/// Returns false for a dead or non-manifold vertex. Cost O(valence^2).
bool VertexLimitMask(const QuadMesh& m, int v, std::vector<std::pair<int, double>>& mask);
/// Limit position of control vertex v (its own position if the mask is unavailable).
Vec3 VertexLimit(const QuadMesh& m, int v);
/// Limit position and unit limit normal (orientation of the faces) of an interior vertex from the
/// closed-form Catmull-Clark tangent masks (Halstead et al. 1993). Returns false for boundary or
/// dead vertices (their normal is not needed by the method) or a degenerate tangent plane.
bool VertexLimitFrame(const QuadMesh& m, int v, Vec3* pos, Vec3* normal);
/// Limit point and unit normal at the centre (u,v) = (1/2,1/2) of the patch of face f: one local
/// Catmull-Clark step turns the face point into a regular valence-4 vertex whose limit is
/// (16 F + 4 sum E_k + sum V_k) / 36 (F the face point, E_k the edge points of the face's edges,
/// V_k the vertex points of its corners). Returns false for a dead face or a degenerate normal.
bool FaceCentreLimit(const QuadMesh& m, int f, Vec3* pos, Vec3* normal);
/// Same, with the Catmull-Clark vertex points of the face's 4 corners supplied by the caller
/// (VertexPoint), so that neighbouring faces share them.
bool FaceCentreLimit(const QuadMesh& m, int f, const Vec3 vertexPoints[4], Vec3* pos, Vec3* normal);
/// Same through a QuadMemo (identical arithmetic, memoized centroids and neighbours).
bool FaceCentreLimit(const QuadMemo& m, int f, const Vec3 vertexPoints[4], Vec3* pos, Vec3* normal);
/// Limit point (and, for an interior edge, unit normal) at the midpoint (u = 1/2 on the edge) of
/// edge k (corner k -> corner k+1) of face f. One local Catmull-Clark step turns the edge point of
/// an interior edge into a regular valence-4 vertex: limit (16 E + 4 (VP_a + VP_b + FP_f + FP_g)
/// + sum of the 4 diagonal edge points) / 36, normal from the regular bicubic tangents, oriented
/// like the faces. A boundary edge's midpoint lies on the boundary cubic B-spline:
/// (VP_a + 4 E + VP_b) / 6 (E the edge midpoint, VP the boundary vertex points); `normal` is then
/// not written and *hasNormal (if given) is false. `vp` (optional) holds the vertex points of
/// the face's 4 corners (VertexPoint). Returns false for a dead face or a degenerate normal.
bool EdgeMidLimit(const QuadMesh& m, int f, int k, const Vec3* vp, Vec3* pos, Vec3* normal, bool* hasNormal = nullptr);
/// Same through a QuadMemo (identical arithmetic).
bool EdgeMidLimit(const QuadMemo& m, int f, int k, const Vec3* vp, Vec3* pos, Vec3* normal, bool* hasNormal = nullptr);
/// Catmull-Clark vertex point (one refinement step) of control vertex v: interior
/// (Q + 2R + (n-3) v)/n, boundary (v_prev + 6 v + v_next)/8.
Vec3 VertexPoint(const QuadMesh& m, int v);
/// Same through a QuadMemo (identical arithmetic).
Vec3 VertexPoint(const QuadMemo& m, int v);

/// Outcome of an interpolation solve.
struct InterpolationStats {
  int iterations = 0;
  double maxResidual = 0;  ///< max |limit(v) - target(v)| over the unknowns at exit (absolute)
  bool converged = false;
};

/// Solves system (1) of the paper, L V_K = V_M, restricted to the unknowns `W` (live vertex
/// indices; all other control points frozen): moves the control points of W so that their limit
/// positions equal `targets` (one per entry of W). Gauss-Seidel sweeps on the limit masks (the
/// paper's fixed-point iteration, in place), until max residual <= `tol` (absolute length) or
/// `maxIter` sweeps. Used locally on a few dozen vertices after each operation (§3.4).
/// Writes through QuadMesh::MoveVertex (journaled inside a transaction).
InterpolationStats SolveInterpolationLocal(QuadMesh& m, const std::vector<int>& W,
                                           const std::vector<Vec3>& targets, double tol, int maxIter = 100);
/// Global version (§3.2): all live vertices are unknowns, targets indexed by vertex slot. Sparse
/// BiCGSTAB (Eigen, diagonal preconditioner, relative tolerance 1e-12) on the assembled limit
/// matrix; Gauss-Seidel polish to `tol` if needed. Cost: O(V) per iteration, ~tens of iterations.
InterpolationStats SolveInterpolationGlobal(QuadMesh& m, const std::vector<Vec3>& targets, double tol,
                                            int maxIter = 500);

}  // namespace quad
}  // namespace vcgext
