#pragma once
/// \file simplify_internal.h
/// The pieces SimplifyToQuads (quad_simplify.cpp) is built from, one concept per file:
/// - simplifier.cpp: one simplification pass (§3.2–3.4: tri-to-quad, interpolation, collapses
///   with local fit until the pass's halting, final checks), on the Simplifier (simplifier.h),
///   whose steps are in simplifier_step.cpp and whose swap sweep is in swap_sweep.cpp;
/// - equalized_layout.cpp: the default layout (the paper's count pass beside the S-cost layout
///   pass, docs/quad.md "Layout");
/// - budget_ladder.cpp: a patch budget and its retries (docs/quad.md "Budget ladder");
/// - coverage.cpp: how closely a cage's limit follows the input, and the coverage guard.
/// Not part of the public API.
#include <limits>
#include <string>
#include <vector>

#include "vcg_ext/core/decimate.h"
#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/progress.h"
#include "vcg_ext/core/stopwatch.h"
#include "vcg_ext/quad/layout_gate.h"
#include "vcg_ext/quad/quad_simplify.h"

namespace vcgext {
namespace simplify_internal {

/// Adds a note to a result's message ("; "-separated).
void AppendMessage(std::string& message, const std::string& note);

/// One simplification (§3.2-3.4) of checked inputs: tri-to-quad (or the given quads) of `start`,
/// interpolation, collapses until the halting of `params`, final checks. With a `gate`, the pass
/// is the layout pass of an overlapped count (quad::LayoutGate: `cancelled`, `gateWait`); with
/// `publishTo`, it is a count pass that publishes its live patch count there.
QuadSimplifyResult SimplifyOnce(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress prog, const std::vector<Quad>* initialQuads,
                                quad::LayoutGate* gate = nullptr, bool* cancelled = nullptr, double* gateWait = nullptr,
                                quad::LayoutGate* publishTo = nullptr);

/// Beyond the paper (issue 13, docs/quad.md "Swap sweep"): the swap sweep
/// (QuadSimplifyParams::swapSweepChain; 0 = nothing) on the finished cage `r`, with the checks of
/// a step (local fit, flip test, thin-part guard against S / M): chains of swaps anywhere on the
/// cage that lower its summed valence defect. Updates r's quads, irregular vertices, valences,
/// flips, `sweepSwaps` and times; test mode (validateEveryOperation) validates every chain.
void SweepCage(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
               const std::vector<double>& M, const QuadSimplifyParams& params, QuadSimplifyResult& r);

/// How closely the interpolating limit of cage `q` follows the input, on a 6 x 6 tessellation per
/// patch: `rms`, the RMS distance from (every k-th of at most ~100k) input vertices to it (to
/// choose between two layouts); with `area`, `unreachedPct`, the share (%) of the input's area
/// (~20k triangles, area-weighted) lying wholly beyond the limit's outline: their points' closest
/// limit points are on the limit's boundary and not along the normal there, so no normal line
/// from the limit reaches them (the paper's projectability, §3.4; an open cage's boundary curve
/// cuts the input's rim, or a flat cage stops short of it). Lateral offsets up to 0.2 per
/// mille of the diagonal or 20 % of the distance (the tessellation's facets: 11 degrees) count as
/// along the normal; the absolute part is the narrowest band beyond the outline that is seen.
/// Infinity / 100 % if the limit cannot be evaluated.
struct Coverage {
  double rms = std::numeric_limits<double>::infinity();
  double unreachedPct = 100.0;
};
Coverage InterpolationCoverage(const TriData& input, const QuadData& q, bool area);

/// RMS distance of the input's vertices to the interpolating limit of cage q (InterpolationCoverage).
double InterpolationRms(const TriData& input, const QuadData& q);

/// RMS distance of the input's vertices to the limit of cage q after the final fit's least squares
/// (FitCatmullClark, default parameters: what the pipeline's next filter does), absolute; infinite
/// when the fit fails.
double FittedRms(const TriData& input, const EmbreeScene& scene, const QuadData& q);

/// The report's limit error of cage q after the same fit: RMS distance of every input vertex to
/// its closest point on the fitted limit (ReferenceToSurfaceError on a tessellation of about one
/// vertex per input triangle, 4..32 segments per patch side), absolute; infinite when the fit
/// fails. FittedRms measures the fit's own data rows, which leave out input vertices farther than
/// the fit's projection reach (10 % of the diagonal): a cage that misses a part of the input
/// entirely can look close by it (oblong-shuffled.off: 2.0 per mille by FittedRms, 53 by this).
/// `minSegments`: the tessellation per patch side at least (the report's metrics: the fit filter's
/// limitSegments, 8; a coarser one adds its chords' error, which differs between cages).
double FittedReferenceRms(const TriData& input, const EmbreeScene& scene, const QuadData& q, int minSegments = 4);

/// FittedReferenceRms (`rms`) and, with `unprojectable`, the report's unprojectable share of the
/// fitted limit (`unprojectablePct`, UnprojectablePercent on the same tessellation, the fit
/// filter's maxDistPercent): what the pipeline's report will say of cage q, and the folds of that
/// tessellation (FoldedTriangles, the report's `folded_triangles_limit`). Infinite RMS (and 100 %,
/// and folds -1) when the fit fails.
struct FittedMeasure {
  double rms = std::numeric_limits<double>::infinity();
  double unprojectablePct = 100.0;
  int folds = -1;
};
FittedMeasure MeasureFitted(const TriData& input, const EmbreeScene& scene, const QuadData& q, int minSegments,
                            bool unprojectable);
/// MeasureFitted as the pipeline's report measures cage q: at the fit filter's limitSegments, on
/// q as the fit filter reads it from MeshLab's layer (LayerRoundTrip: float coordinates, corners
/// that may start elsewhere; the fit amplifies both: triceratops.off @ 400, one cage: 1.081 per
/// mille from double coordinates, 1.101 from float ones).
FittedMeasure MeasureAsReported(const TriData& input, const EmbreeScene& scene, const QuadData& q, bool unprojectable);

/// The swap sweep's guard (QuadSimplifyParams::sweepRmsTolerance): whether the swept cage's
/// measure `swept` is close enough to the unswept one's: its RMS at most `tolerance` (a fraction)
/// above, its unprojectable share at most kSweepUnprojectableSlackPct above.
bool SweepKept(const FittedMeasure& unswept, const FittedMeasure& swept, double tolerance);

/// The end of SimplifyToQuads (quad_simplify.cpp, docs/quad.md "A cage far off"): when cage `r`'s
/// interpolating limit and its fitted one (FittedReferenceRms) stay farther than
/// params.rescueRmsPermille from the input, the same count is laid out again under a budget from
/// `start` (nullptr: the input) and that cage returned when it is closer by the same measure;
/// otherwise `r`, with the check's time and a log note.
QuadSimplifyResult RescueByBudget(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
                                  const std::vector<double>& M, const QuadSimplifyParams& params,
                                  vcg::CallBackPos* cb, const TriData* start, QuadSimplifyResult r);

/// After RescueByBudget (QuadSimplifyParams::coverageFittedPct): a cage `r` whose interpolating
/// limit stays farther than params.rescueRmsPermille from the input and whose fitted limit
/// (MeasureAsReported) leaves more than coverageFittedPct of the input unreached is laid out again
/// from `start` under budgets of 2, 4 and 8 times its patches while that stays so; each relayout
/// kept when it leaves less unreached than the best so far and fits no farther.
QuadSimplifyResult CoverFittedArea(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
                                   const std::vector<double>& M, const QuadSimplifyParams& params,
                                   vcg::CallBackPos* cb, const TriData* start, QuadSimplifyResult r);

/// The coverage guard (QuadSimplifyParams::coverageRmsPermille, coverageUnprojectablePct): a
/// cage `r` (simplified from `start`) whose interpolating limit leaves the input, or leaves part
/// of it unreached by projection, is laid out again with twice the patches.
QuadSimplifyResult CoverageGuard(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                 const std::vector<double>& S, const std::vector<double>& M,
                                 const QuadSimplifyParams& params, Progress& prog, const std::vector<Quad>* initialQuads,
                                 QuadSimplifyResult r);

/// The count pass's coarse start: `start` decimated to `countFaces` triangles (vcglib's quadric
/// collapse, WorkingResolution), not decimated (`decimated` false: count on `start`) when that
/// leaves more slivers than `start` has by kMaxAddedSliverPct, as the first start of a dense input
/// is refused (working_start.h): elephant-with-holes x64's was 91.7 % slivers against its start's
/// 1.8 %, with a vertex of valence 410 whose flip repairs cost the count pass 90 s.
DecimateResult CountStart(const TriData& start, int countFaces);

/// The default layout (QuadSimplifyParams::Layout::Equalized with the M-fitmap, no budget;
/// docs/quad.md "Layout"): the paper's count pass, the S-cost layout pass down to its count (the
/// two overlapped on two threads), and the closer of the two cages when the count ran on `start`.
/// The result before the coverage guard, or an error.
QuadSimplifyResult EqualizedLayout(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                   const std::vector<double>& S, const std::vector<double>& M,
                                   const QuadSimplifyParams& params, Progress& prog,
                                   const std::vector<Quad>* initialQuads);

/// The layout pass: S-cost order without the M test, down to `patches` (the equalized layout,
/// the budget ladder and the coverage guard all run it).
inline QuadSimplifyParams LayoutParams(const QuadSimplifyParams& params, int patches) {
  QuadSimplifyParams lp = params;
  lp.layout = QuadSimplifyParams::Layout::PaperHalting;
  lp.useMFitmap = false;
  lp.targetPatches = patches;
  return lp;
}

/// How a layout trial's cage q is judged: its RMS limit error as the report measures it
/// (MeasureAsReported; triceratops.off @ 400, one cage: 1.081 per mille from double coordinates,
/// 1.101 from float ones, 1.288 in the report of the fit before keepLowestDataRms).
double TrialFittedRms(const TriData& input, const EmbreeScene& scene, const QuadData& q);

/// A budget's layout: BudgetLadder once per weight of TrialValenceWeights(valenceWeight,
/// layoutTrials); kept: the trial that reaches the budget (else comes closest) with the lowest
/// TrialFittedRms, among those with no more flipped patches and vertices than the first.
/// One trial: BudgetLadder alone. The time of the trials not kept and of the fits that compared
/// them is in secondsLayoutTrials (and secondsTotal).
QuadSimplifyResult LayoutTrials(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress& prog, const std::vector<Quad>* initialQuads);

/// A budget of N patches (QuadSimplifyParams::targetPatches, Equalized): the layout pass alone,
/// then a ladder of retries while the thin-part guard (and the flip check) stop it above N + 2 %
/// (docs/quad.md "Budget ladder"). Each retry is kept only when it comes closer to N (a collapse on
/// a thin tube can cascade through the doublets it leaves and land far below it) and covers the
/// input about as well as the first pass (RetryCoversAsWell):
///  1. the guard's tolerance doubled (fandisk at 200 patches: 251 -> 200). Once only: at 4x the
///     tolerance elephant reached 200 patches with 10 % of its area unprojectable;
///  2. a start decimated to 4 N triangles (2 N quads), the guard as given, then (3.) doubled: on
///     the working start the guard keeps every finger of man's fist apart (1 788 patches for 400);
///  4. a start decimated to 2.5 N triangles, the guard doubled (turbine at 400 patches: 507 -> 400).
QuadSimplifyResult BudgetLadder(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress& prog, const std::vector<Quad>* initialQuads);

}  // namespace simplify_internal
}  // namespace vcgext
