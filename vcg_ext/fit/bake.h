#pragma once
/// \file bake.h
/// Outputs of the final fit (Fitmaps §3.5 / §4): the limit surface tessellated per patch, the
/// scalar displacement atlas (one R×R tile per patch) and the displaced surface, an optional
/// normal map, per-wedge UVs of the control quads, the quality metrics of Table 1, and the
/// one-call pipeline FitAndBake (fit + bake + metrics + timings).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <cstring>  // vcglib's callback.h uses strcpy without including it
#include <wrap/callback.h>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/fit/cc_fit.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext {

/// A welded tessellation of the limit surface: each patch is a grid of quads split into
/// triangles; vertices on shared patch edges/corners are shared. Per vertex: the patch and
/// (u,v) it was evaluated at, the unit limit normal, and (when computed) `quality`.
struct LimitTessellation {
  TriData mesh;
  std::vector<Vec3> normal;
  std::vector<int> face;
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> quality;  ///< e.g. signed distance to the reference (absolute units)
  std::vector<int> triPatch;    ///< per triangle: its patch
  int N = 0;                    ///< segments per patch side when all patches have the same count, else 0
};

/// Tessellates the limit of control points `ctrl` over `ls` with N segments per patch side
/// (N×N quads, 2N² triangles per patch, stored patch by patch). Cost: O(F·N²) stencil
/// evaluations (parallel). Preconditions: ls.Ok(), N >= 1, quads.
LimitTessellation TessellateLimit(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int N);
/// Same with segments[f] per side of patch f (>= 1), still welded and watertight: a shared edge
/// carries the union of its two patches' segment points, and the grid cells along an edge with
/// extra points are fanned to them. With equal counts it is exactly the uniform version.
LimitTessellation TessellateLimit(const LimitSurface& ls, const std::vector<Vec3>& ctrl,
                                  const std::vector<int>& segments);

/// Signed distance from each point to the reference surface (closest point; sign > 0 on the
/// side the reference face normal points to). Points farther than maxDist get ±maxDist (+).
std::vector<double> SignedDistanceToReference(const std::vector<Vec3>& pts, const EmbreeScene& ref, double maxDist);

/// The displacement atlas: one square tile per patch. Tile of patch f: tileR[f] texels per side,
/// top-left pixel (tileX[f], tileY[f]) (y downwards, row 0 on top of the PNG); its texel (i,j)
/// holds the signed displacement along the limit normal at (u,v) = (i/(tileR−1), j/(tileR−1)).
/// Texel centres of a tile's corner texels are the patch corners, so wedge UVs at those centres
/// map a tile exactly onto its patch and bilinear texture filtering reproduces the baked grid.
/// Uniform layout (the paper's): every tile R×R in a grid of `cols` columns (patch f at column
/// f % cols, row f / cols). Adaptive layout: tile sizes 2^k+1 chosen per patch
/// (AdaptiveTileResolutions), shelf-packed; `R` is then the largest tile, cols = rows = 0.
struct DisplacementAtlas {
  int R = 0, cols = 0, rows = 0, width = 0, height = 0;
  bool adaptive = false;
  std::vector<int> tileR, tileX, tileY;  ///< per patch
  std::vector<float> disp;          ///< width·height signed displacements (absolute units); 0 outside tiles
  std::vector<std::uint16_t> q16;   ///< quantized: disp ≈ offset + scale · q16
  double scale = 0, offset = 0;
  std::vector<std::uint8_t> normalRGB;  ///< optional 3·width·height object-space normal map ((n+1)/2·255)
  std::vector<std::array<Eigen::Vector2d, 4>> wedgeUV;  ///< per control quad corner, OpenGL convention (v up)
  int misses = 0;                   ///< texels whose normal ray missed (closest-point fallback used)
  /// The surface the atlas displaces. 0: each patch tessellated at its tile's texel spacing,
  /// along the exact limit normal (paper §4). L > 0: the renderer's uniform level-L grid along
  /// its mesh vertex normals (renderer_grid.h: what Blender's Subdivision Surface + Displace
  /// modifiers rebuild). Set before BakeDisplacement; the texel fit and DisplacedSurface follow.
  int rendererLevel = 0;
  int Patches() const { return int(tileR.size()); }
  /// Index into disp / q16 (and / 3 into normalRGB) of patch f's texel (i,j).
  size_t Pixel(int f, int i, int j) const { return size_t(tileY[f] + j) * width + tileX[f] + i; }
  /// Decoded (quantized) displacement of patch f at texel (i,j).
  double Decoded(int f, int i, int j) const { return offset + scale * q16[Pixel(f, i, j)]; }
  /// Texels stored in the tiles (Σ tileR²).
  long long Samples() const;
};

/// Sets `a`'s layout to F uniform R×R tiles (the paper's) and sizes disp (zeros).
void UniformAtlasLayout(DisplacementAtlas& a, int F, int R);
/// Sets `a`'s layout to the given tile sizes, shelf-packed (tallest first) into a near-square
/// image, and sizes disp (zeros).
void AdaptiveAtlasLayout(DisplacementAtlas& a, const std::vector<int>& tileR);

/// Adaptive texel allocation (beyond the paper, see docs/fit.md "Tile sizes"): tile sizes
/// 2^k + 1 (k = 1..6) per patch, Σ tileR² <= `budget`, chosen to minimize the modelled displaced
/// error Σ_f vertices_f · area_f / (tileR_f − 1)² (a reference vertex is off the bilinear layer
/// by about the texel spacing): exactly, by dynamic programming over the budget, when
/// patches × budget/8 <= 4·10⁷ (bunny00: 1.6 M), else by Lagrangian relaxation plus the upgrades
/// that still fit (optimal up to one step's leftover). A budget below 9 texels per patch gives
/// every patch 3×3 (more than the budget). Powers of two make a coarser tile's edge texels a
/// subset of its finer neighbour's, so the two tiles agree exactly along the shared edge (the
/// finer tile's extra edge texels interpolate the coarser's): seamless displacement. Patches
/// that few reference vertices project to get small tiles (down to 3×3) whatever their area:
/// the model counts the error at the reference vertices, the Table-1 measure.
/// `patchVertices`: reference vertices per patch (PatchVertexCounts).
std::vector<int> AdaptiveTileResolutions(const std::vector<double>& patchArea, const std::vector<double>& patchVertices,
                                         double budget);
/// The sample budget of the automatic resolutions: the paper's (total samples ≈ reference
/// vertices), but at least kMinAutoTextureResolution² per patch (see AutoTextureResolution).
double AutoTextureBudget(int referenceVertices, int patches);
/// Area of each patch of a tessellation (by triPatch).
std::vector<double> PatchAreas(const LimitTessellation& t, int patches);
/// Reference vertices whose closest point on the tessellation `t` lies on each patch.
std::vector<double> PatchVertexCounts(const LimitTessellation& t, int patches, const TriData& ref);

/// Resolution of the paper (§4): total samples ≈ reference vertices, R = round(√(nRef/F)), but at
/// least kMinAutoTextureResolution. Decision (beyond the paper): on a coarse reference the paper's
/// rule gives tiles of 2–4 texels (elephant.off, 2.8k vertices, 413 patches: R = 3), and bilinear
/// displacement between so few texels moved the surface off the reference vertices: the displaced
/// surface was worse than the limit (RMS 1.15‰ vs 1.12‰). Measured on that mesh: R = 5/8/12/16
/// give 0.80/0.66/0.41/0.30‰. Eight texels per side cost 64 samples per patch, negligible.
int AutoTextureResolution(int referenceVertices, int patches);
constexpr int kMinAutoTextureResolution = 8;

/// Bakes the displacement atlas: for each texel, the signed distance along the limit normal to
/// the reference (nearest ray hit on either side within maxDist; miss → the closest reference
/// point's offset along the normal). `normalMap`: also bake the reference's interpolated vertex
/// normal at the hit (object space). Cost: F·R² ray casts (parallel).
DisplacementAtlas BakeDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                   const EmbreeScene& scene, int R, double maxDist, bool normalMap);
/// Same into the tiles of a prepared layout (UniformAtlasLayout / AdaptiveAtlasLayout, one tile
/// per patch, every tile >= 2). Texels that stand for the same surface point in several tiles
/// (shared edges and corners) get one value, and a finer tile's extra texels along an edge
/// shared with a coarser tile are interpolated from the coarser one's: the tiles are seamless.
void BakeDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                      const EmbreeScene& scene, double maxDist, bool normalMap, DisplacementAtlas& a);

/// Parameters of FitDisplacement.
struct DisplacementFitParams {
  int iterations = 2;         ///< foot points → solve rounds (foot points recomputed on the new surface)
  double anchorWeight = 0.1;  ///< pull of every texel to its point-sampled value, relative to one reference vertex
};
/// What FitDisplacement did (errors: RMS distance of the reference vertices to the displaced
/// layer before quantization, absolute units).
struct DisplacementFitStats {
  bool fitted = false;        ///< the fit ran (the atlas may still be unchanged: iterations == 0)
  int iterations = 0;         ///< solves kept (0: the point samples were best)
  double rmsBefore = 0, rmsAfter = 0;
};

/// Least-squares displacement (beyond the paper, whose §4 samples each texel by one normal ray):
/// replaces the texel values of a baked atlas `a` by those that make the displaced layer
/// (DisplacedSurface with the same minSegments) closest to the reference vertices, i.e. minimize
///   Σ_x ((x − D(foot_x))·m_x)² + w_a Σ_texel (d − d_ray)²
/// over the texels d: foot_x = closest point of reference vertex x on the displaced layer, m_x
/// the unit normal of the displaced triangle there (point-to-plane linearization), D bilinear in
/// the texels along the limit normals; d_ray = the point-sampled value (the anchor keeps texels
/// no reference vertex sees, and the system definite). Texels on shared tile edges/corners are
/// one unknown, so the tiles stay seamless. Each round recomputes the foot points on the new
/// surface; the best round (by the RMS) is kept, the point samples if no round improves (the
/// atlas is then left exactly as baked). Reference vertices farther than maxDist from the
/// displaced layer (parts the control mesh does not cover, outliers) give no row, and the texels
/// stay within ±maxDist, the bake's own range. Re-quantizes the atlas when a solve is kept. Why: with about one texel per reference vertex, point samples
/// between which the reference is rough or the texels are sparse (stretched patches) leave
/// the reference vertices off the bilinear surface; the fit places the same texels where the
/// reference vertices are. Cost: (iterations+1) closest-point passes over the reference plus a
/// sparse Cholesky of one unknown per texel.
DisplacementFitStats FitDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                     int minSegments, double maxDist, const DisplacementFitParams& p,
                                     DisplacementAtlas& a);
/// Same, on a displaced layer's base already built (DisplacementBase of `a`): FitAndBake builds
/// it once for the fit and DisplacedSurface.
DisplacementFitStats FitDisplacement(const LimitSurface& ls, const TriData& ref, const LimitTessellation& base,
                                     double maxDist, const DisplacementFitParams& p, DisplacementAtlas& a);

/// Triangles of a (displaced) tessellation facing against the limit normals of their corners
/// (sum of the three): folds, where the displacement along converging normals crosses over.
int FoldedTriangles(const LimitTessellation& t);

/// The displaced surface as a renderer shows it: the limit surface tessellated with
/// max(tileR-1, minSegments) segments per side of each patch (welded, TessellateLimit), each
/// vertex moved along the limit normal by the bilinearly filtered (decoded 16-bit) displacement
/// of its patch's tile. Where minSegments <= tileR-1 the vertices sit exactly on the texels. Decision: a tile coarser than the
/// limit layer (automatic R is small when patches are many) must not make the displaced surface
/// coarser than the limit surface it adds detail to (elephant, 944 patches, R = 2: displaced RMS
/// 4.2 permille vs limit 0.74 before this). With a.rendererLevel = L > 0: the uniform level-L
/// grid instead, each vertex moved along its mesh normal (RendererGrid), as Blender rebuilds it.
LimitTessellation DisplacedSurface(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const DisplacementAtlas& a,
                                   int minSegments = 0);
/// The surface DisplacedSurface displaces (its vertices along their normals, undisplaced): the
/// per-tile tessellation with limit normals, or the renderer's grid (a.rendererLevel).
LimitTessellation DisplacementBase(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const DisplacementAtlas& a,
                                   int minSegments);
/// DisplacedSurface of a base already built (DisplacementBase of `a`).
LimitTessellation DisplacedSurface(const LimitSurface& ls, const DisplacementAtlas& a, LimitTessellation base);

/// Table-1 metrics. Errors are one-sided, per reference vertex (unweighted; scans are roughly
/// uniformly sampled): the distance from every reference vertex to its closest point on the
/// surface, RMS and max, in ‰ of the reference bbox diagonal.
struct FitMetrics {
  double rmsLimitPermille = 0, maxLimitPermille = 0;
  double rmsDisplacedPermille = 0, maxDisplacedPermille = 0;
  double maxLimitToRefPermille = 0;  ///< the other direction: tessellation vertices → reference
  /// Area-weighted checks of the displaced layer (AreaSampledDistance): reference → displaced,
  /// and the other direction, displaced → reference (RMS, max). The least-squares displacement
  /// is fitted to the reference vertices; these say it does not just trade the per-vertex figure
  /// for error elsewhere on the surface.
  double rmsDisplacedAreaPermille = 0;
  double rmsDisplacedToRefPermille = 0, maxDisplacedToRefPermille = 0;
  int displacedFolds = 0;  ///< FoldedTriangles of the displaced layer
  int limitFolds = 0;      ///< FoldedTriangles of the dense limit tessellation (zero displacement)
  double unprojectablePct = 0;       ///< % of the reference area not reached by normal projection
};

/// RMS / max distance (absolute) of the reference vertices to `surf`.
std::pair<double, double> ReferenceToSurfaceError(const TriData& ref, const TriData& surf);
/// Same, with a scene already built on the surface.
std::pair<double, double> ReferenceToSurfaceError(const TriData& ref, const EmbreeScene& surf);

/// RMS / max distance (absolute) from the surface `from`, sampled by area, to `to`: per triangle
/// its centroid weighted by its area, or (threePoint) the points (2/3,1/6,1/6), (1/6,2/3,1/6),
/// (1/6,1/6,2/3) weighted by a third of it. Use threePoint when `from`'s triangles are coarse
/// compared to `to`'s features (a chord's centroid is its farthest point: on bunny00's displaced
/// layer the centroid rule gives 2.72 permille where the 3-point rule gives 1.84).
std::pair<double, double> AreaSampledDistance(const TriData& from, const TriData& to, bool threePoint = false);
/// Same, with a scene already built on `to`.
std::pair<double, double> AreaSampledDistance(const TriData& from, const EmbreeScene& to, bool threePoint = false);

/// Share (percent) of the reference area that no normal line from the limit surface reaches
/// first (paper §4 "projectability"): lines along ±normal from the vertices of the dense
/// tessellation `lim` mark the nearest reference triangle they hit (within maxDist); each
/// unmarked triangle gets a second chance from the closest point of its centroid on `lim`
/// (interpolated normal). Cost: |lim| + unmarked ray casts.
double UnprojectablePercent(const LimitTessellation& lim, const TriData& ref, const EmbreeScene& scene, double maxDist);
/// Same, with a scene already built on `lim.mesh` (`limScene`).
double UnprojectablePercent(const LimitTessellation& lim, const EmbreeScene& limScene, const TriData& ref,
                            const EmbreeScene& scene, double maxDist);

/// Cap of the automatic metric tessellation (FitBakeParams::metricSegments): finer changes no
/// figure (bunny00 x16, 382 patches: 79 segments, the reference's density, and 32 give RMS limit
/// 0.881 and max 5.047 / 5.046 permille; 24 gives 0.882) but costs time and memory there
/// (metrics 18.7 -> 12.8 s, peak 1356 -> 1090 MB on a loaded machine, 2026-12-02).
constexpr int kMaxAutoMetricSegments = 32;

/// The automatic metric tessellation per patch side: about one triangle per reference triangle,
/// sqrt(2 refFaces / patches), between `minSegments` (FitBakeParams::limitSegments) and
/// kMaxAutoMetricSegments (never below `minSegments`). The report's metrics (FitAndBake) and the
/// simplification's fitted measures (FittedReferenceRms) use it, so they measure alike.
inline int AutoMetricSegments(long refFaces, int patches, int minSegments) {
  return std::max(minSegments, std::min(kMaxAutoMetricSegments,
                                        int(std::ceil(std::sqrt(2.0 * double(refFaces) / std::max(patches, 1))))));
}

/// Above this share of the reference's area unreached by projection from the limit
/// (FitBakeMetrics::unprojectablePct, in %) the report warns (ResultWarnings).
constexpr double kUnprojectableWarningPct = 1.0;

/// Parameters of FitAndBake.
struct FitBakeParams {
  FitParams fit;
  int limitSegments = 8;          ///< N: output limit layer tessellation per patch side
  int textureResolution = 0;      ///< R per tile side (uniform tiles); 0 = automatic
  bool adaptiveTiles = true;      ///< automatic R: per-patch tiles by area (AdaptiveTileResolutions); false: the paper's one R
  /// Automatic R: the atlas budget (one texel per reference vertex, the paper's) is capped at this
  /// many texels (0 = no cap). Default 2048² = 4 194 304: a 16-bit PNG of 8 MB, and the
  /// displacement fit's system stays at millions of unknowns; scans above ~8 M triangles reach it
  /// (docs/multires.md "Atlas cap" measures what the displaced error costs there).
  int maxTexels = 2048 * 2048;
  bool normalMap = false;         ///< also bake the normal map
  double maxDistPercent = 10.0;   ///< max displacement / projection distance, % bbox diagonal
  /// Tessellation per patch side used for the limit error / projectability; 0 = auto: about one
  /// triangle per reference triangle, sqrt(2 F_ref / patches), between limitSegments and
  /// kMaxAutoMetricSegments.
  int metricSegments = 0;
  bool computeMetrics = true;
  bool fitDisplacement = true;    ///< least-squares texels (FitDisplacement) instead of the paper's point samples
  /// Bake for the surface a renderer rebuilds: the uniform level-L subdivision along its mesh
  /// normals (DisplacementAtlas::rendererLevel = RendererLevel: one grid vertex per texel of the
  /// largest tile), instead of the per-tile tessellation along the limit normal. Blender then
  /// shows the reported displaced error (docs/blender.md); costs a denser displaced layer.
  bool rendererGrid = false;
  DisplacementFitParams displacementFit;
};

/// Everything the plugin / tools write out, plus the report.
struct FitBakeResult {
  std::string error;
  FitResult fit;
  LimitTessellation limit;        ///< N×N per patch, quality = signed distance to the reference
  LimitTessellation displaced;    ///< quality = signed distance to the reference
  DisplacementAtlas atlas;
  DisplacementFitStats displacementFit;
  FitMetrics metrics;
  std::vector<std::pair<std::string, double>> times;  ///< seconds per stage, in order
  double totalSeconds = 0;
  double peakMemoryMb = 0;        ///< process peak RSS at the end (ProcessPeakMemoryMb)
  /// peak RSS (MB) of the stages fit, tessellate, bake, metrics (StagePeakMemoryMb; the first
  /// includes whatever ran since the caller's last StagePeakMemoryMb)
  std::vector<std::pair<std::string, double>> memory;
  int referenceVertices = 0, referenceFaces = 0;
  /// What the user should know about an otherwise valid result (ResultWarnings): also in the
  /// report's "warnings" list and, from the filter, in the log.
  std::vector<std::string> warnings;
};

/// Warnings a valid result still deserves (issue 16): more than 1 % of the reference area
/// unprojectable; a limit surface that stays far from the reference somewhere (max error above
/// 2 % of the bbox diagonal: sharp corners or creases that a smooth Catmull-Clark limit cannot
/// follow with this many patches).
std::vector<std::string> ResultWarnings(const FitBakeResult& r);

/// Fits `control` to `ref` (FitCatmullClark), tessellates the limit, bakes the atlas, builds the
/// displaced surface and measures Table-1 metrics. `scene` must be built on `ref`. On error only
/// `error` is meaningful. Cost: dominated by ray casts (≈ (iterations+3)·|ref| rays).
FitBakeResult FitAndBake(const QuadData& control, const TriData& ref, const EmbreeScene& scene,
                         const FitBakeParams& p = {}, vcg::CallBackPos* cb = nullptr);

/// Human-readable multi-line summary of a result (for the MeshLab log and tools).
std::string FormatReport(const FitBakeResult& r);

}  // namespace vcgext
