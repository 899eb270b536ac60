#pragma once
/// \file loop_tools.h
/// Tools on a LoopSurface: interpolation of the control net (§3.3), per-vertex curvature of the
/// limit surface, and the uniform / curvature-adaptive refinement mesher (§4).
#include <string>
#include <utility>
#include <vector>

#include <cstring>  // wrap/callback.h uses strcpy without including it
#include <wrap/callback.h>

#include "vcg_ext/loop/loop_surface.h"

namespace vcgext {

/// All hard edges of a surface as vertex pairs (interior and boundary), e.g. to build another
/// surface on moved control points with the same tags (creaseAngleDeg = 0 + extraHardEdges).
std::vector<std::pair<int, int>> HardEdgeList(const LoopSurface& s);

// ------------------------------------------------------------------ interpolation (§3.3)
struct LoopInterpolateParams {
  LoopSurfaceParams surface;   ///< hard-edge tagging of the ORIGINAL net (kept for the result)
  double solverTol = 1e-15;    ///< BiCGSTAB relative tolerance
  int maxIterations = 1000;
  double cuspProbe = 1e-3;     ///< barycentric offset from a vertex where the limit normal is probed
  /// Fold detection: the limit normal of the interpolated net is compared with the original face
  /// normal on a barycentric lattice of this order in every face ((L+1)(L+2)/2 - 3 points + the
  /// 3 vertex probes; 6: 28 evaluations per face).
  int cuspLattice = 6;
};
struct LoopInterpolateResult {
  std::string error;
  std::vector<Vec3> X;       ///< new control points: S_inf * X = original vertices
  double residual = 0;       ///< max |S_inf X - x| / bbox diagonal
  int iterations = 0;        ///< BiCGSTAB iterations (max over x, y, z)
  int flippedVertices = 0;   ///< vertices whose limit normal (in an incident face) opposes that face's original normal (Fig. 10 cusps)
  int foldedFaces = 0;       ///< faces where the limit normal at a lattice point (or a vertex probe) opposes the original face normal
  std::vector<int> cuspVertices;  ///< the flipped vertices
  std::vector<int> foldedFaceList;  ///< the folded faces (ascending)
  double seconds = 0;
};
/// Solves S_inf(x_interp) = x (eq. (9)) with Eigen's BiCGSTAB (diagonal preconditioner) on the
/// sparse limit-mask operator (smooth: Loop limit mask; crease: (1,4,1)/6; hard vertex:
/// identity), so that the Loop surface of the new net passes through the original vertices, and
/// detects the cusps / folds of Fig. 10: the limit normal of the new net opposes the original
/// face normal somewhere in a face (lattice probing, `cuspLattice`) or next to a vertex
/// (`cuspProbe`). Typical cause: a strongly non-uniform net (neighbouring vertices much closer
/// than the others), where the interpolating control points overshoot past each other.
/// Cost: O(nnz * iterations) + O(F * L^2) evaluations.
LoopInterpolateResult InterpolateLoopNet(const TriData& net, const LoopInterpolateParams& p = {});

// ------------------------------------------------------------------ curvature
enum class LoopCurvatureKind { Mean = 0, Gauss = 1, MaxAbs = 2, Min = 3, Max = 4 };
/// Curvature of the limit surface at each control vertex's limit point. Regular smooth vertices
/// (valence 6, no hard edge, all incident faces box-spline patches): exact value at the vertex.
/// Extraordinary, crease and corner vertices (only C1 there, curvature undefined or one-sided):
/// the average over the incident faces of the value at barycentric offset `probe` from the
/// vertex (corner weight 1 - 2*probe), principal curvatures averaged separately. Isolated
/// vertices get 0. Unit: 1/length (Gauss: 1/length^2). Cost: O(sum of valences) evaluations.
std::vector<double> LoopVertexCurvature(const LoopSurface& s, LoopCurvatureKind kind, double probe = 0.05);

// ------------------------------------------------------------------ refinement mesher (§4)
struct LoopRefineParams {
  enum class Mode { Uniform, Adaptive };
  Mode mode = Mode::Adaptive;
  int targetFaces = 250000;   ///< stop when the mesh has at least this many triangles
  /// Stop when the largest metric is below this (Adaptive: max|k| * area / bbox diagonal;
  /// Uniform: area / diagonal^2). 0: target count only.
  double tolerance = 0;
  double batchFraction = 0.25;  ///< share of the faces (largest metric first) split per pass
  int swapPasses = 2;           ///< max-min angle swap rounds after each insertion pass (first over the faces the pass changed, then over the faces swapped and their neighbours)
  /// Adaptive: metric = (max|k| + flatWeight / diag) * area, so flat regions still refine slowly.
  double flatWeight = 1.0;
  /// Refuse (LoopRefineResult::error) a refinement whose memory (EstimateLoopRefineMemoryMb)
  /// would exceed this many MB; 0: 80 % of the memory available when it starts (CheckMemory).
  double maxMemoryMb = 0;
};
struct LoopRefineResult {
  std::string error;
  TriData mesh;                 ///< every vertex on the limit surface
  std::vector<int> paramFace;   ///< per vertex: control face ...
  std::vector<double> paramV, paramW;  ///< ... and (v, w) in it
  int passes = 0, insertions = 0, edgeSplits = 0, swaps = 0;
  double maxMetric = 0;
  double seconds = 0;
};
/// Refines the limit surface: starts from the control net's topology with vertices at their
/// limit positions, then repeatedly inserts centroids (the parameter-space centroid mapped onto
/// the surface) into the faces with the largest metric (area, or max principal curvature x area
/// at the centroid), splits hard edges of refined faces at their parameter midpoint (on the
/// crease curve), and sweeps max-min-angle edge swaps (hard edges are never swapped). Stops at
/// `targetFaces` or `tolerance`. Cost: O(target) evaluations. Progress through `cb`.
LoopRefineResult RefineLoopSurface(const LoopSurface& s, const LoopRefineParams& p, vcg::CallBackPos* cb = nullptr);

/// Memory (MB) that refining to `targetFaces` triangles takes in MeshLab's "Loop Surrogate: Refine
/// Surface": the refiner's arrays, its result, the filter's vcglib mesh and the layer's copy
/// (measured, loop_tools.cpp kLoopRefineBytesPerTriangle). RefineLoopSurface refuses a target
/// beyond LoopRefineParams::maxMemoryMb before any work: the kernel would otherwise kill MeshLab.
double EstimateLoopRefineMemoryMb(long targetFaces);

}  // namespace vcgext
