#pragma once
/// \file loop_surface.h
/// Loop subdivision surface as CAD-free surrogate geometry (Persson, Aftosmis, Haines,
/// "On the use of Loop subdivision surfaces for surrogate geometry"): a triangle mesh becomes
/// the control net of a Loop surface that can be evaluated anywhere at (triangle, v, w).
///
/// Parameterization (paper §3.1): barycentrics u + v + w = 1 of a control triangle F[t] =
/// (c0, c1, c2); the point is parameterised by (v, w): corner c0 at (0,0), c1 at (1,0),
/// c2 at (0,1) (the same convention as vcgext::LimitSurface's (u,v) for Loop).
///
/// Evaluation (our own kernel, not OpenSubdiv):
///  - regular triangles (three smooth valence-6 corners, or a straight crease through the
///    patch with three faces on the triangle's side of every crease corner) use the quartic
///    box spline of eq. (8) with the paper's 12x15 matrix phi (6); across a straight crease the
///    12-point neighbourhood is completed with ghost points a + b - c (so the crease is the
///    cubic B-spline of the crease polygon, §2.4);
///  - other triangles are subdivided locally until the query point lies in a regular
///    sub-triangle (§3.2, Fig. 8), with the paper's "nudge" onto the centre sub-triangle at
///    depth 25 (the nudge moves the point by <= 2^-25 of the triangle, i.e. ~3e-8 of an edge).
///    The first `cacheDepth` levels of every irregular triangle are precomputed (monomial
///    coefficients of each regular tile, one flat breadth-first arena). Below that, the local
///    net around the one irregular corner is self-similar: one level is a fixed matrix S (and the
///    three regular children fixed 12-point gathers T_c), shared by all nets of the same topology
///    (Stam's structure without the eigenbasis), so each deeper level is one small mat-vec. Nets
///    that are not self-similar (rare: 36 of 7344 on fandisk) are subdivided on the fly. The
///    evaluation is exact (no Gregory/approximate end caps).
/// Hard edges (§2.4): boundary edges, edges whose dihedral angle exceeds `creaseAngleDeg`, and
/// `extraHardEdges`. Edge points on hard edges use the 1-D rule (1); vertices with exactly two
/// hard edges use the 1-D rule (2)/(3); vertices with more than two hard edges (and
/// non-manifold vertices) are hard vertices and stay fixed; a vertex with one hard edge (a
/// "dart") uses the smooth Loop rule.
///
/// Thread safety: the surface is immutable after construction; all const queries may run
/// concurrently.
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Construction parameters of LoopSurface.
struct LoopSurfaceParams {
  /// Edges whose dihedral angle (angle between the two face normals) exceeds this, in degrees,
  /// are hard. <= 0 or >= 180 disables the test. Default 40 (the paper: "a simple dihedral
  /// angle criterion"; fandisk's features are all >= 45 degrees, its smooth parts < 25).
  double creaseAngleDeg = 40.0;
  /// Additional hard edges as vertex pairs (e.g. from a MeshLab selection); each must be an
  /// edge of the mesh.
  std::vector<std::pair<int, int>> extraHardEdges;
  /// Levels of local subdivision precomputed per irregular triangle (0..10). Deeper queries
  /// use the shared self-similar level matrices (see the file comment). Memory is ~1.9 KB per
  /// level per irregular triangle (fandisk: 21 MB at 2, 45 MB at 5). From 2 on, almost all
  /// nets are self-similar; 0 or 1 make deep queries slow.
  int cacheDepth = 2;
  /// Maximum local subdivision depth before the paper's nudge (Fig. 8 uses 25).
  int maxDepth = 25;
  /// Nets with a vertex of higher valence are refused with a clear error. Near an extraordinary
  /// vertex an evaluation subdivides its whole ring (local nets of ~valence vertices), so building
  /// the surface costs O(valence²) round it. Measured (2026-12-01, 2 cores): a cone's apex of
  /// valence 2000 builds in 4.1 s and refines to 100k triangles in 4.3 s; UV-sphere poles of
  /// valence 500 in 0.4 s + 0.4 s (docs/robustness.md). 0 = no limit.
  int maxValence = 2048;
  /// Memory (MB) the surface may take (EstimateLoopSurfaceMemoryMb); 0: 80 % of the memory
  /// available when it is built (CheckMemory). The cache depth is lowered, down to 0, until the
  /// surface fits (CacheDepth() tells the one used: evaluations get slower, not wrong); a net
  /// that does not fit even then is refused with an error (Ok() false).
  double maxMemoryMb = 0;
};

/// The cache depth `p` asks for, within the levels a surface caches (0..10).
inline int RequestedCacheDepth(const LoopSurfaceParams& p) { return std::max(0, std::min(p.cacheDepth, 10)); }

/// Memory (MB) a LoopSurface of `irregularFaces` triangles subdivided locally and `regularFaces`
/// box-spline triangles takes with `cacheDepth` cached levels (measured, loop_surface.cpp
/// kLoopBytes*): ~9 kB per irregular triangle at the default depth 2, so a 5 M-triangle scan
/// would take ~40 GB.
double EstimateLoopSurfaceMemoryMb(long irregularFaces, long regularFaces, int cacheDepth);

/// Everything an evaluation returns. Derivatives are with respect to (v, w).
struct LoopEval {
  Vec3 P = Vec3::Zero();
  Vec3 Dv = Vec3::Zero(), Dw = Vec3::Zero();
  Vec3 Dvv = Vec3::Zero(), Dvw = Vec3::Zero(), Dww = Vec3::Zero();
  Vec3 N = Vec3::Zero();  ///< unit normal (Dv x Dw normalised; zero if degenerate)
  int depth = 0;          ///< local subdivision depth used (0: regular control triangle)
};

/// Principal curvatures k1 >= k2 and unit directions. Sign: k = -II/I with II = x_ij . N, so a
/// convex surface with outward normal (counter-clockwise faces seen from outside) has k > 0.
struct LoopCurvature {
  double k1 = 0, k2 = 0;
  Vec3 d1 = Vec3::Zero(), d2 = Vec3::Zero();
  double Mean() const { return 0.5 * (k1 + k2); }
  double Gauss() const { return k1 * k2; }
  double MaxAbs() const { return std::abs(k1) > std::abs(k2) ? std::abs(k1) : std::abs(k2); }
};

/// Principal curvatures from first and second derivatives (fundamental forms).
LoopCurvature CurvatureFromDerivatives(const LoopEval& e);

/// Vertex type of the control net (§2.4).
enum class LoopVertexType : unsigned char { Smooth = 0, Crease = 1, Corner = 2 };

class LoopSurface {
 public:
  LoopSurface();
  /// Builds the surface: validates the net (indices, NaN/inf coordinates, degenerate faces,
  /// non-manifold or inconsistently oriented edges, isolated vertices allowed), tags hard
  /// edges/vertices and precomputes the per-triangle patches (OpenMP). On failure Ok() is
  /// false and Error() says what is wrong. Cost: O(F * 4^0 * cacheDepth) patch builds.
  LoopSurface(const TriData& net, const LoopSurfaceParams& p = {});
  ~LoopSurface();
  LoopSurface(LoopSurface&&) noexcept;
  LoopSurface& operator=(LoopSurface&&) noexcept;

  bool Ok() const { return error_.empty(); }
  const std::string& Error() const { return error_; }
  const TriData& Net() const { return net_; }
  int NumFaces() const { return int(net_.F.size()); }
  int NumVertices() const { return int(net_.V.size()); }

  /// Evaluates position, derivatives (order <= 2), normal at (face, v, w), v, w >= 0,
  /// v + w <= 1 (values slightly outside are clamped). Thread-safe. Returns false for a bad
  /// face index. Cost: ~100 ns for a cached tile, a few microseconds per on-the-fly level.
  bool Evaluate(int face, double v, double w, LoopEval& out, int order = 2) const;
  /// Position only (cheaper).
  Vec3 Position(int face, double v, double w) const;
  /// Curvature at (face, v, w) (order-2 evaluation).
  LoopCurvature Curvature(int face, double v, double w, LoopEval* eval = nullptr) const;

  /// Limit position of control vertex i (the limit masks of Fig. 3 / eq. (3)).
  Vec3 VertexLimit(int i) const;
  /// Limit positions of all control vertices for other control positions X (same topology):
  /// rows of the sparse limit operator S-infinity (see LimitMatrix).
  std::vector<Vec3> VertexLimits(const std::vector<Vec3>& X) const;
  /// The limit operator S-infinity as triplets (row, col, weight), nV x nV (§3.3).
  void LimitMatrixTriplets(std::vector<int>& rows, std::vector<int>& cols, std::vector<double>& w) const;

  // --- topology queries (used by snapping, refinement, tests)
  LoopVertexType VertexType(int i) const { return vtype_[i]; }
  /// Whether the edge F[f][k] -> F[f][(k+1)%3] is hard.
  bool EdgeHard(int f, int k) const { return hard_[f][k] != 0; }
  /// Face across edge k of face f (edge F[f][k] -> F[f][(k+1)%3]), -1 on a boundary.
  int FaceAcross(int f, int k) const { return adj_[f][k]; }
  int NumHardEdges() const { return numHardEdges_; }
  int NumCornerVertices() const;
  int NumIrregularFaces() const { return numIrregularFaces_; }
  /// Whether the face is evaluated directly by the box spline (no local subdivision).
  bool FaceIsRegular(int f) const;
  /// A (face, corner) incident to vertex i, or (-1,-1) if isolated.
  std::pair<int, int> VertexCorner(int i) const { return vcorner_[i]; }
  /// Memory of the precomputed patches, bytes.
  size_t CacheBytes() const;
  /// The cache depth used: LoopSurfaceParams::cacheDepth, or lower when that would not fit the
  /// memory (LoopSurfaceParams::maxMemoryMb).
  int CacheDepth() const { return cacheDepth_; }
  /// Bounding-box diagonal of the control net (computed once at construction).
  double NetDiagonal() const;

  /// Internal representation, public for the implementation file only.
  struct Impl;

 private:
  std::string error_;
  TriData net_;
  std::vector<LoopVertexType> vtype_;
  std::vector<std::array<unsigned char, 3>> hard_;
  std::vector<std::array<int, 3>> adj_;
  std::vector<std::pair<int, int>> vcorner_;
  int numHardEdges_ = 0;
  int numIrregularFaces_ = 0;
  int cacheDepth_ = 0;
  LoopSurfaceParams params_;
  std::unique_ptr<Impl> impl_;
};

/// Result of a closest-point query (§2.1).
struct LoopSnapResult {
  int face = -1;
  double v = 0, w = 0;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  double distance = 0;
  int iterations = 0;      ///< Newton/descent iterations in total
  int faceMoves = 0;       ///< moves to a neighbouring triangle
  bool converged = false;  ///< first-order optimality reached (|grad| <= tol)
  bool usedFallback = false;
};

struct LoopSnapParams {
  int maxIterations = 60;
  /// Convergence: |tangential component of (x - p)| <= tol * bbox diagonal.
  double relTol = 1e-12;
};

/// Closest point on the limit surface to `p` (§2.1): Newton iteration on (v, w) minimising
/// |x(v,w) - p|^2, moving to the neighbouring triangle opposite the most negative barycentric
/// when the iterate leaves the triangle. Starts at (face, v, w) if face >= 0, otherwise at the
/// closest point of the control net (vcgext::EmbreeScene, `netScene` must be built on
/// surf.Net(); if null, a brute-force search over the net is used). Fallback when Newton stalls:
/// damped gradient steps with backtracking, then restarts from the faces around the best
/// point found. Thread-safe.
class EmbreeScene;
LoopSnapResult SnapToLoopSurface(const LoopSurface& surf, const Vec3& p, const EmbreeScene* netScene,
                                 int face = -1, double v = 1.0 / 3, double w = 1.0 / 3,
                                 const LoopSnapParams& sp = {});

}  // namespace vcgext
