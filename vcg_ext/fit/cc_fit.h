#pragma once
/// \file cc_fit.h
/// Global least-squares fit of a Catmull-Clark control mesh to a reference triangle mesh
/// (Panozzo et al. 2011, "Fitmaps", §3.5 Final Fitting, improved):
///  - every patch P is sampled on a k×k grid of cell centres, k = ⌊√(c·n·|P|/|M|)⌋ clamped to
///    [minK, maxK] (n = reference vertices, |M| = reference area, |P| = area of the initial limit
///    patch, c = samplesPerVertex);
///  - each sample's row holds its *exact* limit stencil (OpenSubdiv Bfr, vcgext::LimitSurface),
///    not the paper's bicubic Bézier approximation of irregular patches;
///  - the vertex rows of system (1) (limit position of every control vertex) are added with
///    weight `vertexWeight`;
///  - targets = projection phi of the current limit sample onto the reference along the limit
///    normal (nearest hit on either side within maxProjectionPercent of the reference bbox
///    diagonal; misses fall back to the closest reference point within the same distance);
///  - normal equations (AᵀWA + λI + μΔᵀΔ) X = AᵀWT + λX_prev factorized once with
///    Eigen::SimplicialLDLT (the matrix depends only on the fixed samples) and re-solved at each
///    project → solve iteration until the RMS sample-to-target distance stops improving.
/// Regularization: λ = dampingWeight · mean(diag(AᵀWA)) pulls towards the previous iterate (a
/// Levenberg-style damping that vanishes at convergence: the fixed point is the unregularized
/// least-squares fit); μ = smoothWeight · mean(diag(AᵀWA)) penalizes the uniform Laplacian of the
/// control net (default 0: off; it biases the fit).
#include <string>
#include <vector>

#include <cstring>  // vcglib's callback.h uses strcpy without including it
#include <wrap/callback.h>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

class LimitSurface;

/// How the project → solve iterations measure the distance of the limit to the reference.
enum class FitMethod {
  /// The paper's §3.5: every limit sample is pulled to its projection phi along the limit normal
  /// (point-to-point, x, y, z separable, one factorization). Converges slowly: the tangential part
  /// of each pull holds the surface back (first-order "PDM" of Wang, Pottmann & Liu 2006).
  PointToPoint,
  /// Tangent-distance minimization (the "TDM" of Wang, Pottmann & Liu 2006, the family of the SDM
  /// the paper suggests in §3.5), two-sided: (a) the paper's limit samples, each pulled to the
  /// tangent plane of the reference at its projection phi, and (b) one row per reference vertex,
  /// pulled onto the tangent plane of the limit at its foot point (closest limit point, refined
  /// by Gauss-Newton on the exact limit) — (b) minimizes exactly the reported per-vertex error
  /// and reaches reference parts no limit normal hits (ear tips). Tangential components keep the
  /// weight `tangentWeight` (makes the 3V×3V system definite). Refactorized every iteration.
  TangentDistance
};

/// Parameters of FitCatmullClark. Distances in percent of the reference bbox diagonal.
struct FitParams {
  double samplesPerVertex = 1.0;       ///< c: total samples ≈ c · reference vertices (paper: 1)
  int minK = 2;                        ///< minimum samples per patch side (paper: implied ≥ 1; we use 2)
  int maxK = 32;                       ///< cap on samples per patch side (bounds the cost of huge patches)
  double vertexWeight = 1.0;           ///< weight of the vertex rows of system (1) relative to a sample row
  double maxProjectionPercent = 10.0;  ///< max |t| of the projection along the normal, % bbox diagonal
  int maxIterations = 8;               ///< project → solve iterations (at least 1)
  double minImprovement = 0.01;        ///< stop when the RMS improves by less than this fraction
  double dampingWeight = 1e-3;         ///< λ relative to mean(diag(AᵀWA)): pull to the previous iterate
  /// TangentDistance: when a solve raises the objective, go back to the best iterate and solve
  /// again with 10× the damping, at most this many times (Levenberg–Marquardt). 0 = stop at the
  /// first increase (before 2026-12-02: on man.off with ~6 input vertices per patch the first
  /// solve overshot and the fit kept the unfitted cage).
  int dampingRetries = 3;
  double smoothWeight = 0.0;           ///< μ relative to mean(diag(AᵀWA)): control-net Laplacian (off; both methods)
  double maxMissFraction = 0.5;        ///< error if more limit samples than this miss the reference by ray
  FitMethod method = FitMethod::TangentDistance;  ///< PointToPoint = the paper's literal §3.5
  double tangentWeight = 0.01;         ///< TangentDistance: weight of the tangential residual components (1 = point-to-point)
  /// TangentDistance: weight of the paper's limit-sample (and vertex) rows against the
  /// reference-vertex rows. 0.25 since 2026-12-04 (was 1): the sample rows' targets are ray hits
  /// that can land on the wrong sheet of a thin part, the data rows measure what the report
  /// measures; on 30 cages of 10 meshes the RMS limit error fell on every one (× 0.875 on
  /// average, docs/fit.md "The sample rows' weight").
  double sampleWeight = 0.25;
  double dataWeight = 1.0;             ///< TangentDistance: weight of a reference-vertex row relative to a limit-sample row
  int footpointSegments = 4;           ///< TangentDistance: tessellation (per patch side) used to seed the foot points
  /// TangentDistance: at most this many reference-vertex rows (every k-th vertex, k = ⌈n / max⌉,
  /// each weighted k× so the balance with the sample rows stays); 0 = every vertex. A fit of a
  /// few hundred patches is decided long before 200k points: on dense scans (bunny00 ×16,
  /// 600k vertices) the foot points of every vertex were most of the fit's time
  /// (docs/multires.md). The reported errors are measured on every vertex.
  int maxDataRows = 200000;
  /// TangentDistance: return the iterate with the lowest RMS reference vertex → limit (the error
  /// the report measures) instead of the one with the lowest objective (samples and vertices
  /// mixed). Near convergence the two row sets pull against each other and the iterates alternate
  /// between a low-sample-RMS and a low-data-RMS phase; which one has the lower objective flips
  /// with rounding, and the reported error flipped with it by up to 15 % (triceratops @400:
  /// 1.288 vs 1.101 permille from the same cage). Damping follows the objective; the fit also
  /// goes on (up to maxIterations) while the objective still improves and the data RMS improves
  /// by minImprovement or more. docs/fit.md "Which iterate is kept".
  bool keepLowestDataRms = true;
  /// TangentDistance: a system of at least this many unknowns (3 per control vertex) is
  /// factorized at the first solve only; the later solves are conjugate gradients preconditioned
  /// with that factorization, from the current iterate, to a relative residual of 1e-10
  /// (FactorPreconditioner); it is refactorized when they do not converge in 50 steps, and at the
  /// next solve when they needed more than 10. 0: refactorize every iteration. The default leaves every cage of the pipeline (up to a few thousand patches) as
  /// before; a 55k-quad cage (166k unknowns) spent 110 of its fit's 129 s in 8 factorizations
  /// (docs/fit.md "Large control meshes").
  int reuseFactorizationFrom = 30000;
  /// Refuse (FitResult::error) a fit whose memory (EstimateFitMemoryMb) would exceed this many MB;
  /// 0: 80 % of the memory available when the fit starts (AvailableMemoryMb). A vertex of valence
  /// n gives its faces stencils of ~2n + 8 control points and the fit's local blocks their square:
  /// measured on a fan of quads round one vertex over a 200k-vertex reference, valence 64 took
  /// 1.1 GB in 26 s, 256 took 8.7 GB in 441 s, 1 024 exhausted 24 GB and was killed
  /// (docs/robustness.md "Poles in a control mesh").
  double maxMemoryMb = 0;
};

/// Outcome of FitCatmullClark. When `error` is non-empty, only `error` is meaningful.
struct FitResult {
  std::string error;
  QuadData control;                    ///< the fitted control mesh (same connectivity as the input)
  int patches = 0;
  int irregularVertices = 0;           ///< interior valence ≠ 4 or boundary valence ≠ 3
  int degeneratePatches = 0;           ///< zero-area control quads or degenerate limit normal at the centre
  int firstDegeneratePatch = -1;
  int samples = 0;                     ///< sample rows (without the vertex rows)
  int minKUsed = 0, maxKUsed = 0;
  std::vector<double> rmsPerIteration; ///< RMS sample→target distance (absolute) at each projection
  double rayMissFraction = 0;          ///< share of samples whose normal ray missed (last projection)
  int iterations = 0;                  ///< solves performed
  int dampingRetries = 0;              ///< TangentDistance: solves redone with 10× damping (FitParams::dampingRetries)
  std::vector<double> dataRmsPerIteration;  ///< TangentDistance: RMS reference vertex → limit (foot points), absolute
  std::vector<double> objectivePerIteration;///< TangentDistance: weighted RMS of all rows (the stopping criterion)
  int keptIteration = -1;              ///< TangentDistance: index (in the per-iteration vectors) of the returned iterate
  int factorizations = 0;              ///< TangentDistance: factorizations of the normal equations
  int conjugateGradientSteps = 0;      ///< TangentDistance: steps of the solves that reused one (reuseFactorizationFrom)
  double secondsSetup = 0, secondsFactor = 0, secondsProject = 0, secondsSolve = 0, seconds = 0;
};

/// Fits the control points of `control` (pure quads, manifold, consistently oriented) so that
/// its Catmull-Clark limit surface approximates `ref` (paper §3.5). `scene` must be built on `ref`.
/// Errors: empty/invalid control mesh (LimitSurface validation), empty reference, scene not ok,
/// limit samples mostly missing the reference (control far away), more memory than allowed
/// (FitParams::maxMemoryMb, checked before any row is built). Degenerate patches are counted.
/// Cost: O(S·s²) assembly (S samples, s ≈ 16–40 stencil entries, ~2n round a vertex of valence n), one sparse LDLT of size
/// #control vertices, and per iteration S ray casts + 3 triangular solves.
FitResult FitCatmullClark(const QuadData& control, const TriData& ref, const EmbreeScene& scene,
                          const FitParams& p = {}, vcg::CallBackPos* cb = nullptr);

/// The fit's memory in MB beyond its inputs, estimated before any row is built: per face f with
/// m_f patch points (LimitSurface::NumPatchPoints) and r_f rows (its k_f² samples plus, for
/// TangentDistance, its area share of the reference-vertex rows),
/// kFitBytesPerBlockEntry · m_f² (the local block and its scatter map) +
/// kFitBytesPerStencilEntry · r_f · m_f (the stored stencils). `kOf` and `area` per face as the
/// fit plans them (samples per side, limit area).
double EstimateFitMemoryMb(const LimitSurface& ls, const FitParams& p, const std::vector<int>& kOf,
                           const std::vector<double>& area, int refVertices);

}  // namespace vcgext
