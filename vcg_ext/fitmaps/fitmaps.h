#pragma once
/// \file fitmaps.h
/// S- and M-Fitmaps (Panozzo et al. 2011, §3.1): per-vertex estimates of how well a single
/// cubic patch models the surface around each vertex (S: error growth a^{1/4} of E(r) = a r^4)
/// and how far a patch may extend before normal projection breaks (M: largest radius whose
/// share of un-hit triangles stays below tau).
#include <string>
#include <vector>

#include <vcg/complex/complex.h>
#include <wrap/callback.h>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/far_spikes.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/pipeline_memory.h"

namespace vcgext {

/// Ratio of consecutive radii of the resolution-independent grid (FitmapParams::minRadiusPercent
/// > 0): the paper's grid on its own reference scan, bunny00 (9 radii from its average edge
/// length, 0.5 % of the diagonal, to 25 %: (0.4006 / 0.008106)^(1/8) = 1.6283, rounded down so that
/// r_h / q^8 stays above r_0), so bunny00 keeps its radii
/// down to the floor.
inline constexpr double kAnchoredRadiusRatio = 1.628;

/// Parameters of ComputeFitmaps. Lengths are relative to the bounding-box diagonal where noted.
/// Decisions where the paper is ambiguous are listed in docs/fitmaps.md.
struct FitmapParams {
  enum class Mode {
    Fast,       ///< bounded work per vertex (default); agreement with Reference in docs/fitmaps.md
    Reference,  ///< the paper's literal O(n·|B|) computation (slow: minutes on 75k triangles)
  };
  double tauPercent = 1.0;         ///< tau: tolerated area share of flipped (un-hit) triangles, percent
  int numRadii = 9;                ///< number of radii r_0..r_h (paper: h = 8, i.e. 9 radii), 1..64
  double maxRadiusPercent = 25.0;  ///< r_h in percent of the bbox diagonal (paper: 1/4 = 25%)
  /// The smallest radius, in percent of the bbox diagonal; selects the radius grid (an
  /// experiment, not used by the filters: docs/multires.md "Radii that do not depend on the
  /// resolution" has what it measured; bench_quad --rmin):
  /// - 0: the paper's grid, numRadii radii spaced geometrically from r_0 = the average edge length
  ///   to r_h. Its radii move with the mesh's resolution, and so does the M-fitmap where no
  ///   radius passes (it falls back to r_0: along the creases of a CAD part the patches shrink
  ///   with the edges; fandisk 430 patches, made 4x denser 750).
  /// - > 0: a grid that does not depend on the resolution: r_h / q^k, k = 0, 1, ..., with
  ///   q = kAnchoredRadiusRatio, down to max(this, r_0); numRadii is not used.
  double minRadiusPercent = 0.0;
  Mode mode = Mode::Fast;
  unsigned seed = 1;               ///< random sampling seed (results are deterministic per seed)
  /// A radius enters the S-fitmap's fit E(r) = a r^4 only if its neighbourhood holds at least
  /// this many vertices (a cubic has 10 coefficients; with fewer than ~1.5x as many points the
  /// residual says little). The M-fitmap tests every radius (a ridge-regularised cubic).
  int minFitPoints = 15;
  /// Optional: compute only these vertices (indices into TriData::V). Empty = all. Others get
  /// S = 0, M = 0 and computed[i] = 0. Per-vertex values do not depend on the subset.
  std::vector<int> vertices;
  /// Fast mode: target number of (sub-sampled) points per neighbourhood. Radius r_i is evaluated
  /// on the coarsest level of a vertex hierarchy whose neighbourhood of radius r_i still holds
  /// about this many points, and interpolated to the vertices (see docs/fitmaps.md).
  int fastPointsPerFit = 40;
  /// Fast mode: target points of the per-vertex S fits at the radii >= r_h / 2.5 (the ones that
  /// carry the S-fitmap: E(r_i) weighs (r_i / r_h)^4 in a).
  int fastPointsPerSFit = 96;
  /// Fast mode: the per-vertex S fits run at the points of this hierarchy level (their own
  /// frames) and are interpolated to the other vertices; 0 = at every vertex (slower).
  int fastSLevel = 0;
  /// Fast mode: the levels above are chosen by the mesh's mean area per vertex; where the density
  /// is far from uniform (a dense object on a large sparse floor, pieces scanned at different
  /// resolutions) a radius on level 0 is pushed to a coarser level when the ball of the dense part
  /// (the 10th percentile of the vertex areas) would hold more than this many times the target
  /// points (fastPointsPerFit, fastPointsPerSFit): without it bunny00 on a floor 20 times its size
  /// took 108 s instead of 1.4 (every ball of r_5 held the whole bunny). 0 = off.
  double fastDenseBallFactor = 256;
  /// Fast mode: sampled surface points per neighbourhood for the flipped-share estimate.
  int fastFlipSamples = 16;
  /// Fast mode: how a sampled mesh point x (on face t) counts as hit.
  enum class FlipEstimator {
    /// The paper's forward ray, cast back from the cubic above x (same (u,v)) along its
    /// normal: hit iff it first hits t. Mimics Reference mode's finite sampling.
    ForwardSelf,
    /// Exact coverage: x is the first hit of the normal line through its closest point on the
    /// cubic (the limit of Reference mode for infinitely many samples; more permissive).
    Coverage,
  };
  /// Default Coverage. Decision (docs/fitmaps.md, "Which flipped share"): at the paper's sample
  /// density (~2 rays per face) the literal estimate mostly counts faces its few rays happen
  /// to miss, so on a smooth scan M depends on the sampling density (bunny00 median reference
  /// M 0.021 at factor 4, 0.057 at factor 32) and at tau = 1% caps every patch near 2% of the
  /// diagonal (2886 patches on bunny00 vs the paper's 506). Coverage measures what M is for,
  /// the loss of projection, agrees with a dense literal reference (Spearman 0.81) and gives
  /// 322 / 188 patches on bunny00 at tau 1% / 10% (paper: 506 / 218).
  FlipEstimator fastFlipEstimator = FlipEstimator::Coverage;
  /// Reference mode: the M-fitmap's sample count is referenceSampleFactor * n_M |B| / |M|
  /// (paper: 4, i.e. twice the vertex density). Larger values make the literal estimate converge
  /// to the exact coverage (FlipEstimator::Coverage; see docs/fitmaps.md).
  double referenceSampleFactor = 4.0;
  /// Keep the per-radius measurements E(r_i) and flipped shares in the result (diagnostics).
  bool keepPerRadius = false;
  /// Bounded cost on dense meshes (paper §4; docs/multires.md): a mesh with more triangles than
  /// this is decimated to this many (decimate.h, the same M' as the simplification's), the
  /// Fitmaps are computed on M' and interpolated to every vertex at its closest point on M'
  /// (barycentric). 0 = at every vertex of the mesh (the default of the library; the filters
  /// use their "working resolution"). Fast mode without a vertex subset only.
  int workingFaces = 0;
  /// The vcg entry point refuses (an error, the mesh untouched) a mesh whose Fitmaps would need
  /// more memory than this many MB (EstimatePipelineMemoryMb); 0: 80 % of the memory available
  /// when it starts (CheckMemory).
  double maxMemoryMb = 0;
};

/// The radii r_0..r_h of ComputeFitmaps (ascending, absolute): `r0` the average edge length,
/// `rh` = max(r0, maxRadiusPercent of `diag`), `diag` the bbox diagonal; see
/// FitmapParams::minRadiusPercent for the two grids.
std::vector<double> FitmapRadii(double r0, double rh, double diag, const FitmapParams& p);

/// Per-vertex results, indexed like the TriData's V (unreferenced vertices: S = 0, M = r_0).
/// Values are always finite.
struct FitmapResult {
  std::string error;          ///< non-empty: nothing else is meaningful
  std::vector<double> S;      ///< S-fitmap a^{1/4} (unit length^{-3/4}: a has unit length^{-3})
  std::vector<double> M;      ///< M-fitmap, a radius (absolute length), one of `radii`
  std::vector<double> radii;  ///< the radii used, absolute
  std::vector<char> computed; ///< 1 where S/M were computed (all vertices unless Params::vertices)
  int unreferenced = 0;       ///< vertices in no face (S = 0, M = r_0)
  int fallbackNormals = 0;    ///< vertices whose area-weighted normal vanished (PCA normal used)
  int noFit = 0;              ///< computed vertices where no radius had minFitPoints points (S = 0)
  int levels = 1;             ///< Fast mode: levels of the vertex hierarchy used
  /// With Params::keepPerRadius: E(r_i) and the flipped share of vertex v at [v * radii.size() + i];
  /// -1 where not measured (radius skipped, vertex not computed, M stopped at an earlier radius).
  std::vector<double> perRadiusE, perRadiusFlipped;
  std::vector<int> radiusLevel;  ///< Fast mode: hierarchy level each radius is evaluated on
  double seconds = 0;         ///< wall time
  double secondsLevels = 0, secondsCoarse = 0;  ///< Fast mode: wall time at the end of these stages
  int workingFaces = 0;        ///< triangles the Fitmaps were computed on (0: the mesh itself)
  double secondsDecimate = 0, secondsTransfer = 0;  ///< with Params::workingFaces
  /// repairs made on the working copy (vcg entry point; see input_prep.h) and on the working
  /// resolution (zero-area faces flipped), and warnings
  std::vector<std::string> notes, warnings;
};

/// Computes both Fitmaps of `m` (paper §3.1.2–3.1.3). `scene` must be built on `m`.
/// Per vertex p and radius r_i: the neighbourhood B_i = vertices reached by a breadth-first
/// traversal from p that never leaves the ball of radius r_i (a connected region); a cubic height
/// field over p's tangent plane (area-weighted normal) fitted in the least-squares sense; its RMS
/// residual E_i = sqrt(sum res^2 / n); a = sum E_i r_i^4 / sum r_i^8; S = a^{1/4}. M = the
/// largest r_i such that every radius r_1..r_i has an area share of un-hit triangles < tau.
/// Preconditions: none (invalid input gives `error`); degenerate faces, boundaries, several
/// components, non-manifold and unreferenced vertices are handled (finite values).
/// Cost: Fast mode O(n · k) with k bounded per vertex (about 3 CPU-seconds on 37.7k vertices);
/// Reference mode O(n · |B|) with |B| up to the whole mesh (minutes). OpenMP-parallel.
/// Progress is reported from the calling thread only.
FitmapResult ComputeFitmaps(const TriData& m, const EmbreeScene& scene, const FitmapParams& p,
                            vcg::CallBackPos* cb = nullptr);

/// Names of the per-vertex float attributes that hold the results on a vcg mesh.
inline const char* kFitmapSAttr = "FitmapS";
inline const char* kFitmapMAttr = "FitmapM";

/// vcg entry point: computes the Fitmaps on the layer's working copy (input_prep.h: polygonal
/// layers as triangles, duplicates merged, re-oriented, non-manifold vertices split; non-manifold
/// edges, non-orientable input or a mesh too large for the memory (FitmapParams::maxMemoryMb)
/// are an error) and stores them in the per-vertex float
/// attributes FitmapS / FitmapM (created if missing); vertices in no face get 0. On error the
/// mesh is untouched and `result.error` says why. `result.S` / `result.M` are indexed like the
/// working copy.
template <class MeshType>
FitmapResult ComputeFitmaps(MeshType& m, const FitmapParams& p, vcg::CallBackPos* cb = nullptr) {
  FitmapResult res;
  res.error = CheckPipelineMemory(PipelineStep::Fitmaps, m.fn, p.maxMemoryMb);
  if (!res.error.empty()) return res;
  WorkingCopy w = PrepareQuadPipelineCopy(m);
  if (!w.error.empty()) { res.error = w.error; return res; }
  EmbreeScene scene(w.mesh);
  if (!scene.Ok()) { res.error = scene.Error(); return res; }
  res = ComputeFitmaps(w.mesh, scene, p, cb);
  if (!res.error.empty()) return res;
  // the working copy's repairs first, then what the computation itself reports
  res.notes.insert(res.notes.begin(), w.notes.begin(), w.notes.end());
  res.warnings.insert(res.warnings.begin(), w.warnings.begin(), w.warnings.end());
  const std::vector<double> S = ToLiveVertices(w, res.S, 0.0), M = ToLiveVertices(w, res.M, 0.0);
  auto hS = vcg::tri::Allocator<MeshType>::template GetPerVertexAttribute<float>(m, kFitmapSAttr);
  auto hM = vcg::tri::Allocator<MeshType>::template GetPerVertexAttribute<float>(m, kFitmapMAttr);
  size_t i = 0;
  for (auto& v : m.vert) {
    if (v.IsD()) continue;
    hS[v] = float(S[i]);
    hM[v] = float(M[i]);
    ++i;
  }
  return res;
}

}  // namespace vcgext
