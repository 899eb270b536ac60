// Glue for "Fitmap Quad Simplification" (paper §3.2–3.4): current triangle (or quad) layer +
// its Fitmaps -> a NEW layer with the adaptive pure-quad control mesh. The input is not modified.
#include <cmath>
#include <QString>

#include <algorithm>
#include <chrono>
#include <climits>
#include <sstream>

#include "filter_table.h"
#include "glue.h"
#include "vcg_ext/core/far_spikes.h"
#include "vcg_ext/core/decimate.h"
#include "vcg_ext/core/pipeline_memory.h"
#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/fitmaps/fitmaps.h"
#include "vcg_ext/quad/close_holes.h"
#include "vcg_ext/quad/scan_artifacts.h"
#include "vcg_ext/quad/quad_simplify.h"
#include "vcg_ext/quad/working_start.h"

namespace fitmapquad {

void InitQuadParams(const MeshDocument& /*md*/, RichParameterList& par) {
  const vcgext::QuadSimplifyParams d;
  par.addParam(RichFloat(param::kTau, float(vcgext::FitmapParams().tauPercent), "Tolerance tau (%)",
                         "M-fitmap tolerance. The layer's Fitmaps are used when they were computed "
                         "with this tau; otherwise they are computed (default radii, fast mode) "
                         "without modifying the layer."));
  par.addParam(RichInt(param::kTargetPatches, d.targetPatches, "Target patches (0 = automatic)",
                       "Stop at this many patches (with the equalized layout the budget is reached "
                       "whatever tau: the M-fitmap test is not applied; a layer with too few "
                       "triangles for it starts from its midpoint refinement); 0 = the count of the "
                       "paper's halting criterion (simplify until no feasible collapse is left)."));
  par.addParam(RichBool(param::kUseMFitmap, d.useMFitmap, "M-fitmap test",
                        "Refuse collapses that make a patch larger than the M-fitmap allows "
                        "(projectability). Off: only the S-fitmap cost; needs a target count."));
  par.addParam(RichBool(param::kEqualizedLayout, d.layout == vcgext::QuadSimplifyParams::Layout::Equalized,
                        "Equalized layout (the paper's count)",
                        "With target 0 and the M-fitmap test: the paper's halting is run on a coarse "
                        "start mesh only to count its patches, and that many patches are then laid out "
                        "by the S-fitmap cost alone (sizes follow the fitting error, not projectability). "
                        "Off: the paper literally (collapse until the M-fitmap blocks every collapse); "
                        "about 2x the limit error on bunny00 (docs/quad.md, Layout)."));
  par.addParam(RichBool(param::kEdgeSwaps, d.edgeSwaps, "Edge swaps",
                        "Valence-improving edge swaps after each collapse (fewer irregular vertices)."));
  par.addParam(RichFloat(param::kRegularity, float(d.valenceWeight), "Regularity weight (0 = off)",
                         "Beyond the paper: in the layout pass (and under a patch budget) a collapse's "
                         "S-fitmap cost is multiplied by (1 + w)^d, d the change of its corners' summed "
                         "valence defect, so collapses that make corners regular come first. 0 = the "
                         "S cost alone. 1 about halves the irregular vertices at a budget, while the limit "
                         "error moves by -40 % to +80 % depending on the mesh (docs/quad.md, Regularity)."));
  par.addParam(RichInt(param::kSwapSweep, d.swapSweepChain, "Swap sweep (swaps per chain, 0-5, 0 = off)",
                       "Beyond the paper: after the last collapse, every chain of up to this many edge "
                       "swaps anywhere on the cage that lowers the summed valence defect (a pair of "
                       "singularities moved together and cancelled) is applied, each chain checked "
                       "like a collapse. 3: a fifth to a third fewer irregular vertices at the same "
                       "count, the limit error and the unprojectable area a little higher on average; "
                       "0 = the paper (swaps only after collapses; docs/quad.md, Swap sweep)."));
  par.addParam(RichFloat(param::kSweepTolerance, float(100 * d.sweepRmsTolerance),
                         "Swap sweep tolerance (%, negative = no check)",
                         "With the swap sweep: both cages, with and without its chains, are fitted and "
                         "measured as the report will measure them, and the chains are undone unless the "
                         "swept cage's RMS limit error is at most this many percent above the unswept one's "
                         "and it leaves no more of the input unprojectable (two fits more). Negative: the "
                         "sweep's cage is kept unchecked (docs/quad.md, Swap sweep)."));
  par.addParam(RichInt(param::kLayoutTrials, d.layoutTrials, "Layout trials (with a target, 1-5)",
                       "Beyond the paper, with a target patch count: lay the patches out this many times "
                       "with different regularity weights (yours, then 0, 0.25, 1, 0.05) and keep the cage "
                       "whose fitted limit surface is closest to the input (RMS). The error of one layout "
                       "moves by +-25 % with tiny changes of the collapse order, so more trials give a "
                       "lower error for about as many times the simplification's time (docs/quad.md, "
                       "Layout trials). 1 = one layout."));
  par.addParam(RichFloat(param::kGuard, float(d.deviationFactor), "Thin-part guard (x F_M, 0 = off)",
                         "Beyond the paper: a collapse is undone when the new limit surface (patch "
                         "centres and edge midpoints) ends farther from the input than this fraction "
                         "of the M-fitmap. Keeps thin parts (legs, ears) apart; 0 = the paper's "
                         "behaviour (fewer patches, faster, may merge thin parts)."));
  par.addParam(RichInt(param::kWorkingFaces, kDefaultWorkingFaces, "Working resolution (triangles, 0 = full)",
                       "Paper §4 (large meshes): the control mesh starts from the input decimated to "
                       "this many triangles (vcglib's quadric edge collapse, topology and boundary "
                       "kept) when the input has more; projections, Fitmaps and every error still "
                       "refer to the full input. 0 starts from the full input."));
  par.addParam(RichInt(param::kFirstWorkingFaces, kDefaultFirstWorkingFaces,
                       "First start of a dense input (triangles, 0 = none)",
                       "An input with more triangles than the working resolution is first simplified "
                       "from its decimation to this many (at least 4x the target patches), and from the "
                       "working resolution only when that start limited the result (a count above 1/16 of "
                       "its triangles, or a missed target). About a third faster on dense scans, the "
                       "same errors on average; 0 = always the working resolution (docs/multires.md)."));
  par.addParam(RichFloat(param::kCloseHoles, float(vcgext::CloseHolesParams().maxDiagonalPercent),
                         "Close small holes for the layout (% of diagonal, 0 = none)",
                         "Beyond the paper: the layer's holes smaller than this share of its bounding-box "
                         "diagonal (and those of at most 6 straight sides below 10 %) are closed in the "
                         "simplification's working copy (vcglib's ear cutting, as Close Holes), so the cage "
                         "is laid out across them as across the surface around instead of keeping a ring of "
                         "patches round each; the fit, the displacement and every reported error still refer "
                         "to the layer as it is. 0 = every hole stays a hole of the cage (docs/robustness.md, "
                         "Many small holes)."));
  par.addParam(RichBool(param::kValidate, d.validateEveryOperation, "Validate every operation (slow)",
                        "Test mode: full mesh validity check after every local operation."));
}

namespace {
// Where the simplification starts (docs/quad.md "Budget survey"): the working resolution rule, and
// with a budget of N patches a start that can reach it. An input whose pairing gives fewer than N
// quads (fewer than 2N + 2 triangles) starts from its midpoint refinement (x4 per step, at most
// three steps; helmet, 1 000 triangles, stopped at 486 patches for 1 000); a dense one is
// decimated to no fewer than 4N triangles (2N quads: room for the collapses to choose). Inputs
// that could already reach N are not refined: rotor (1 200 triangles) refined for 400 patches
// stopped at 683 instead of 515 (the thin-part guard refuses more collapses on more quads).
vcgext::StartMeshParams BudgetStartParams(int workingFaces, int targetPatches, int inputFaces) {
  const long reach = targetPatches > 0 ? 2L * targetPatches + 2 : 0, room = targetPatches > 0 ? 4L * targetPatches : 0;
  const long maxRefined = std::max<long>(kMinWorkingFaces, 64L * inputFaces);
  const int minFaces = int(std::min(std::max<long>(kMinWorkingFaces, reach), maxRefined));
  const int startFaces = workingFaces > 0 ? int(std::min<long>(std::max<long>(workingFaces, room), INT_MAX)) : 0;
  return {startFaces, kDefaultFitmapsWorkingFaces, minFaces, kMaxStartValence};
}

// The filter's parameters as QuadSimplifyParams (and tau, the working resolution, the holes to
// close); false after ctx.Fail on a value out of range.
bool QuadParams(GlueContext& ctx, vcgext::QuadSimplifyParams& p, double& tau, int& workingFaces, int& firstFaces,
                double& closeHolesPct) {
  tau = ctx.par.getFloat(param::kTau);
  p.targetPatches = ctx.par.getInt(param::kTargetPatches);
  p.useMFitmap = ctx.par.getBool(param::kUseMFitmap);
  p.layout = ctx.par.getBool(param::kEqualizedLayout) ? vcgext::QuadSimplifyParams::Layout::Equalized
                                                      : vcgext::QuadSimplifyParams::Layout::PaperHalting;
  p.edgeSwaps = ctx.par.getBool(param::kEdgeSwaps);
  p.valenceWeight = ctx.par.getFloat(param::kRegularity);
  p.swapSweepChain = ctx.par.getInt(param::kSwapSweep);
  p.sweepRmsTolerance = ctx.par.getFloat(param::kSweepTolerance) / 100.0;
  p.layoutTrials = ctx.par.getInt(param::kLayoutTrials);
  p.validateEveryOperation = ctx.par.getBool(param::kValidate);
  p.deviationFactor = ctx.par.getFloat(param::kGuard);
  // Coverage guard at 5 tau (the count let the limit stray five times the tolerance), at most
  // 10 % of the diagonal (docs/robustness.md "Closed thin shapes").
  p.coverageRmsPermille = std::min(50.0 * tau, 100.0);
  // A start too coarse (its cage keeps more than half its quads, its limit farther than tau):
  // refined (docs/quad.md "A start too coarse").
  p.startRmsPermille = 10.0 * tau;
  // A cage still that far off, fitted: laid out again under a budget of its count (docs/quad.md
  // "A cage far off").
  p.rescueRmsPermille = 10.0 * tau;
  workingFaces = ctx.par.getInt(param::kWorkingFaces);
  if (workingFaces < 0) return ctx.Fail("the working resolution must be >= 0 triangles");
  closeHolesPct = ctx.par.getFloat(param::kCloseHoles);
  if (!(closeHolesPct >= 0 && closeHolesPct <= 100)) return ctx.Fail("close small holes must be in [0, 100] percent");
  firstFaces = ctx.par.getInt(param::kFirstWorkingFaces);
  if (firstFaces < 0) return ctx.Fail("the first start of a dense input must be >= 0 triangles");
  if (!(p.deviationFactor >= 0 && p.deviationFactor <= 100)) return ctx.Fail("the thin-part guard must be in [0, 100]");
  if (!(p.valenceWeight >= 0 && p.valenceWeight <= 100)) return ctx.Fail("the regularity weight must be in [0, 100]");
  if (p.swapSweepChain < 0 || p.swapSweepChain > 5) return ctx.Fail("the swap sweep must be in [0, 5] swaps per chain");
  if (!(p.sweepRmsTolerance <= 10)) return ctx.Fail("the swap sweep tolerance must be at most 1000 percent");
  if (p.layoutTrials < 1 || p.layoutTrials > 5) return ctx.Fail("the layout trials must be in [1, 5]");
  if (!(tau >= 0 && tau <= 100)) return ctx.Fail("tau must be in [0, 100] percent");
  if (p.targetPatches < 0) return ctx.Fail("target patches must be >= 0");
  if (!p.useMFitmap && p.targetPatches == 0)
    return ctx.Fail("without the M-fitmap test a target patch count is needed (it would collapse everything)");
  return true;
}

// A pure-quad layer (faux edges pairing its triangles) is simplified from its quads (`given`,
// remapped to the working copy) when they are usable and enough for the budget.
bool LayerQuads(GlueContext& ctx, MeshModel& in, vcgext::WorkingCopy& w, int targetPatches, vcgext::QuadData& given) {
  int faux = 0;
  for (const auto& f : in.cm.face)
    if (!f.IsD())
      for (int k = 0; k < 3; ++k) faux += f.IsF(k) ? 1 : 0;
  bool useQuads = false;
  if (faux > 0) {
    int flipped = 0;
    std::string err = vcgext::ImportQuads(in.cm, given, nullptr, &flipped);
    // a tiny quad layer (a 6-quad cube) is better started from its refined triangles
    // (and one with fewer quads than the budget from its triangles, refined for room)
    useQuads = err.empty() && int(given.F.size()) * 2 >= kMinWorkingFaces && int(given.F.size()) >= targetPatches &&
               vcgext::RemapQuadsToWorkingCopy(w, given.F);
    if (useQuads && flipped > 0)
      ctx.log("Fitmap Quad Simplification: " + std::to_string(flipped) +
              " of the layer's triangles were stored reversed against their neighbours: its quads read oriented "
              "coherently, each piece as most of its faces (the layer untouched)");
    ctx.log(useQuads ? "Fitmap Quad Simplification: the layer is pure quads: simplifying its quads"
                     : "Fitmap Quad Simplification: the layer's polygons are not usable as quads (" +
                           (err.empty() ? std::string("repaired on the working copy, or too few") : err) +
                           "): simplifying its triangles");
  }
  return useQuads;
}

// The layer's small holes closed in the working copy (close_holes.h): the simplification, its
// Fitmaps when computed here and its warnings see the closed copy; the fit filter the layer.
void CloseHolesForLayout(GlueContext& ctx, vcgext::WorkingCopy& w, double maxDiagonalPercent) {
  vcgext::CloseHolesParams cp;
  cp.maxDiagonalPercent = maxDiagonalPercent;
  const vcgext::CloseHolesResult c = vcgext::CloseSmallHoles(w, cp);
  ctx.Value("closed_holes", c.closed);
  if (!c.refused.empty())
    ctx.log("Warning: Fitmap Quad Simplification: the small holes were left open (" + c.refused + ")");
  if (c.closed == 0) return;
  std::ostringstream n;
  n << "Fitmap Quad Simplification: closed " << c.closed << " of the layer's " << c.holes << " holes for the layout ("
    << c.closedAreaPct << " % of its area; those below " << maxDiagonalPercent << " % of the diagonal, or of at most "
    << cp.maxEdges << " straight sides below " << cp.maxEdgesDiagonalPercent << " %"
    << (c.islands ? "; " + std::to_string(c.islands) + " round another sheet left open" : std::string())
    << (c.pinched ? "; " + std::to_string(c.pinched) + " left open whose closing would pinch a vertex" : std::string())
    << (c.skipped ? "; " + std::to_string(c.skipped) + " left open" : std::string())
    << "): the cage spans them, the fit and its report refer to the layer as it is";
  ctx.log(n.str());
}

// The Fitmaps on the working copy: the layer's if computed with this tau (`fromLayer`), else
// computed here (the layer untouched; `times` then starts with their stage). False after ctx.Fail.
bool QuadFitmaps(GlueContext& ctx, MeshModel& in, const vcgext::WorkingCopy& w, const vcgext::EmbreeScene& scene,
                 double tau, std::vector<double>& S, std::vector<double>& M, StageTimes& times, bool& fromLayer) {
  times = GetStageTimes(in.cm);
  auto hS = vcg::tri::Allocator<CMeshO>::FindPerVertexAttribute<float>(in.cm, vcgext::kFitmapSAttr);
  auto hM = vcg::tri::Allocator<CMeshO>::FindPerVertexAttribute<float>(in.cm, vcgext::kFitmapMAttr);
  fromLayer = vcg::tri::Allocator<CMeshO>::IsValidHandle<float>(in.cm, hS) &&
              vcg::tri::Allocator<CMeshO>::IsValidHandle<float>(in.cm, hM) && std::abs(GetFitmapTau(in.cm) - tau) < 1e-6;
  if (fromLayer) {
    S = vcgext::AttributeOnWorkingCopy(w, in.cm, hS);
    M = vcgext::AttributeOnWorkingCopy(w, in.cm, hM);
    ctx.log("Fitmap Quad Simplification: using the layer's Fitmaps (tau = " + std::to_string(tau) + "%)");
  } else {
    const std::string memErr = vcgext::CheckPipelineMemory(vcgext::PipelineStep::Fitmaps, in.cm.fn, 0);
    if (!memErr.empty()) return ctx.Fail("Fitmap Quad Simplification: Fitmaps: " + memErr);
    vcgext::FitmapParams fp;
    fp.tauPercent = tau;
    fp.workingFaces = kDefaultFitmapsWorkingFaces;
    vcgext::FitmapResult fr = vcgext::ComputeFitmaps(w.mesh, scene, fp, ctx.cb);
    if (!fr.error.empty()) return ctx.Fail("Fitmap Quad Simplification: Fitmaps: " + fr.error);
    S = fr.S;
    M = fr.M;
    times = {{"fitmaps", fr.seconds}};
    ctx.log("Fitmap Quad Simplification: computed Fitmaps (tau = " + std::to_string(tau) + "%) in " +
            std::to_string(fr.seconds) + " s");
  }
  return true;
}

// The swap sweep's guard (QuadSimplifyParams::sweepRmsTolerance): what it measured and chose.
void ReportSweepGuard(GlueContext& ctx, const vcgext::QuadSimplifyResult& r, const vcgext::QuadSimplifyParams& p,
                      const vcgext::TriData& tri) {
  ctx.Value("sweep_refused_chains", r.sweepRefusedChains);
  const double pm = 1000 / vcgext::BBoxDiagonal(tri.V);
  // the guard's two measures, each what the fit filter's report will say of that cage (-1: unguarded)
  ctx.Value("sweep_swept_rms_permille", r.sweepGuarded ? r.sweepSweptRms * pm : -1.0);
  ctx.Value("sweep_unswept_rms_permille", r.sweepGuarded ? r.sweepUnsweptRms * pm : -1.0);
  if (!r.sweepGuarded) return;
  std::ostringstream g;
  g << "Fitmap Quad Simplification: the swap sweep's cage fits to " << r.sweepSweptRms * pm << " per mille RMS, "
    << r.sweepSweptUnprojectablePct << " % unprojectable, the unswept one to " << r.sweepUnsweptRms * pm << ", "
    << r.sweepUnsweptUnprojectablePct << " %: ";
  if (r.sweepRefusedChains > 0)
    g << "its " << r.sweepRefusedChains << " chains are undone (more than " << 100 * p.sweepRmsTolerance
      << " % farther or " << vcgext::kSweepUnprojectableSlackPct << " % more unprojectable)";
  else
    g << "kept";
  g << "; the two fits took " << r.secondsSweepGuard << " s";
  ctx.log(g.str());
}

// The simplification's first log line: counts, valences, operations, refusals and times.
void LogQuadSummary(GlueContext& ctx, const vcgext::QuadSimplifyResult& r, std::chrono::steady_clock::time_point t0) {
  std::ostringstream log;
  log << "Fitmap Quad Simplification: " << r.initialPatches << " -> " << r.patches << " patches, "
      << r.irregularVertices << " irregular vertices; tri-to-quad: " << vcgext::quad::ToString(r.triToQuadPath)
      << "; valences:";
  for (size_t v = 0; v < r.valenceHistogram.size(); ++v)
    if (r.valenceHistogram[v]) log << " " << v << ":" << r.valenceHistogram[v];
  log << "; " << r.collapses << " collapses, " << r.swaps << " swaps, " << r.doublets << " doublets, "
      << r.boundaryCorners << " boundary corners, " << r.sweepSwaps << " swap chains in the final sweep; refused: " << r.rejectedByM << " by the M-fitmap, "
      << r.rejectedTopology << " by topology, " << r.rejectedFlip << " by flips, " << r.rejectedDeviation << " by the thin-part guard; final flipped patches "
      << r.flippedPatches << "; checks on several threads in " << int(std::lround(100 * r.parallelStepShare))
      << " % of the steps; time: tri-to-quad " << r.secondsTriToQuad << " s, initial fit "
      << r.secondsInitialFit << " s, simplification " << r.secondsSimplify << " s, total "
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s";
  ctx.log(log.str());
}

// What the budget's retries did (the ladder, the layout trials, the start refinement) and the
// warning when the budget was still missed.
void LogBudgetRetries(GlueContext& ctx, const vcgext::QuadSimplifyResult& r, const vcgext::QuadSimplifyParams& p) {
  if (r.budgetRelaxations > 0) {
    std::ostringstream b;
    b << "Fitmap Quad Simplification: the thin-part guard stopped the budget of " << p.targetPatches
      << " patches at " << r.budgetFromPatches << "; laid out again";
    if (r.budgetStartFaces > 0) b << " from a start decimated to " << r.budgetStartFaces << " triangles";
    b << " with the guard's tolerance at " << r.budgetDeviationFactor << " x the M-fitmap";
    if (r.budgetRelaxations != 2) b << " (doubled)";
    b << ": " << r.patches << " patches (the ladder's rungs run, in order: " << r.budgetRungsRun << ")";
    ctx.log(b.str());
  }
  if (r.layoutTrialsRun > 1) {
    std::ostringstream t;
    t << "Fitmap Quad Simplification: " << r.layoutTrialsRun << " layout trials (valence weights";
    for (double w : vcgext::TrialValenceWeights(p.valenceWeight, r.layoutTrialsRun)) t << " " << w;
    t << "): kept the one with weight " << r.trialValenceWeight << " (the closest fitted limit; weight: patches, "
      << "RMS per mille: " << r.layoutTrialsSummary << "); the others took " << r.secondsLayoutTrials << " s";
    ctx.log(t.str());
  }
  if (r.startRefinements > 0)
    ctx.log("Fitmap Quad Simplification: the cage of the start mesh (" + std::to_string(r.startRefinedFrom) +
            " patches) stayed off the input (its start mesh too coarse for it): simplified again from the start refined " +
            std::to_string(r.startRefinements) + " time(s) at edge midpoints: " + std::to_string(r.patches) + " patches");
  if (p.targetPatches > 0 && !vcgext::BudgetReached(r.patches, p.targetPatches))
    ctx.log("Warning: Fitmap Quad Simplification: the budget of " + std::to_string(p.targetPatches) +
            " patches was not reached: " + std::to_string(r.patches) +
            " patches: no collapse left that the checks allow (M-fitmap, thin-part guard, topology, flips)");
}

// The equalized layout's count pass and which layout was kept.
void LogLayout(GlueContext& ctx, const vcgext::QuadSimplifyResult& r, const vcgext::TriData& tri) {
  if (r.countPatches <= 0) return;
  const double pm = 1000 / vcgext::BBoxDiagonal(tri.V);
  std::ostringstream c;
  c << "Fitmap Quad Simplification: " << r.countPatches << " patches from the paper's halting (M-fitmap test) on a "
    << r.countStartFaces << "-triangle start mesh; ";
  if (r.keptPaperLayout)
    c << "kept that cage: its interpolating limit is closer to the input than the equalized layout's (RMS "
      << r.paperLayoutRms * pm << " vs " << r.equalizedLayoutRms * pm << " per mille)";
  else
    c << "those patches laid out by the S-fitmap cost alone (equalized layout"
      << (r.paperLayoutRms > 0 ? ", interpolating limit RMS " : "")
      << (r.paperLayoutRms > 0 ? std::to_string(r.equalizedLayoutRms * pm) + " vs the paper's " +
                                     std::to_string(r.paperLayoutRms * pm) + " per mille"
                               : std::string())
      << "; the M-fitmap refusals above are the counting pass's)";
  if (r.keptPaperLayout) {
    c << "; the other passes (the equalized layout, a coarse count) added " << r.secondsCount << " s";
  } else {
    c << "; the count pass took " << r.secondsCount + r.secondsCountOverlapped << " s";
    if (r.secondsCountOverlapped > 0)
      c << " (" << r.secondsCountOverlapped << " s of it on a second thread beside the layout pass)";
  }
  ctx.log(c.str());
}

// The coverage guard's relayout, when it ran.
void LogCoverage(GlueContext& ctx, const vcgext::QuadSimplifyResult& r, const vcgext::QuadSimplifyParams& p,
                 const vcgext::TriData& tri) {
  const bool keptFitted = r.coverageFittedCheckPct >= 0 && r.coverageFittedCheckPct <= p.coverageUnprojectablePct;
  if (r.coverageRelayouts <= 0 && keptFitted) {
    std::ostringstream k;
    k << "Fitmap Quad Simplification: the " << r.patches << "-patch cage's interpolating limit leaves "
      << r.layoutUnprojectablePct << " % of the input's area unreached by projection (limit "
      << p.coverageUnprojectablePct << " %, as round the rims of small holes); fitted, it leaves "
      << r.coverageFittedCheckPct << " %: kept";
    ctx.log(k.str());
    return;
  }
  if (r.coverageRelayouts <= 0) return;
  const double pm = 1000 / vcgext::BBoxDiagonal(tri.V);
  std::ostringstream g;
  g << "Fitmap Quad Simplification: the " << r.coverageFromPatches << "-patch cage did not cover the input "
    << "(its interpolating limit stays " << r.coverageFromRms * pm
    << " per mille of the diagonal from it, RMS, and leaves " << r.coverageFromUnprojectablePct
    << " % of its area unreached by projection; limits 5 tau and " << p.coverageUnprojectablePct
    << " %: the M-fitmap did not stop the collapses, as on thin closed parts, flat open ones and sharp "
       "solids)";
  if (r.coverageFittedCheckPct >= 0) g << " and, fitted, " << r.coverageFittedCheckPct << " %";
  g << "; laid out again with " << r.patches << " patches (RMS " << r.layoutRms * pm << " per mille, unreached "
    << r.layoutUnprojectablePct << " %";
  if (r.layoutFittedUnprojectablePct >= 0) g << ", fitted " << r.layoutFittedUnprojectablePct << " %";
  g << ")";
  ctx.log(g.str());
}

// The log lines and returned values of a simplification (r, for the parameters p, on `tri`).
void ReportQuads(GlueContext& ctx, const vcgext::QuadSimplifyResult& r, const vcgext::QuadSimplifyParams& p,
                 const vcgext::TriData& tri, const vcgext::EmbreeScene& scene, std::chrono::steady_clock::time_point t0) {
  LogQuadSummary(ctx, r, t0);
  LogBudgetRetries(ctx, r, p);
  const vcgext::SecondSheets sheets = vcgext::FindSecondSheets(tri, scene);
  for (const std::string& w : {vcgext::DebrisWarning(r.quads, vcgext::BBoxDiagonal(tri.V)),
                               vcgext::HolesWarning(tri, r.quads), vcgext::DoubledWallWarning(sheets, r.quads),
                               p.targetPatches > 0 ? std::string() : vcgext::ThinSheetWarning(sheets, r.quads)})
    if (!w.empty()) ctx.log("Warning: Fitmap Quad Simplification: " + w);
  // (what the warnings measure, for scripts: shares of the input's area, in %)
  ctx.Value("thin_sheet_pct", sheets.thin.areaPercent);
  ctx.Value("doubled_wall_pct", sheets.doubled.areaPercent);
  ctx.Value("budget_relaxations", r.budgetRelaxations);
  ctx.Value("start_refinements", r.startRefinements);
  ctx.Value("rescued_from_patches", r.rescuedFromPatches);
  ctx.Value("fitted_coverage_relayouts", r.fittedCoverageRelayouts);
  ctx.Value("patches", r.patches);
  ctx.Value("irregular_vertices", r.irregularVertices);
  ctx.Value("sweep_chains", r.sweepSwaps);
  ReportSweepGuard(ctx, r, p, tri);
  ctx.Value("initial_patches", r.initialPatches);
  ctx.Value("count_patches", r.countPatches);
  ctx.Value("kept_paper_layout", r.keptPaperLayout ? 1 : 0);
  ctx.Value("seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  LogLayout(ctx, r, tri);
  ctx.Value("coverage_relayouts", r.coverageRelayouts);
  if (r.layoutUnprojectablePct >= 0) ctx.Value("cage_unprojectable_pct", r.layoutUnprojectablePct);
  if (r.coverageFittedCheckPct >= 0) ctx.Value("cage_fitted_unprojectable_pct", r.coverageFittedCheckPct);
  if (r.layoutFittedUnprojectablePct >= 0)
    ctx.Value("relaid_cage_fitted_unprojectable_pct", r.layoutFittedUnprojectablePct);
  LogCoverage(ctx, r, p, tri);
  if (!r.message.empty()) ctx.log("Fitmap Quad Simplification: " + r.message);
}
// The start's notes and warnings, and the first start's outcome when one was tried; its stage
// times ("first_start": the first start's decimation and simplification when it was not kept).
void LogWorkingStart(GlueContext& ctx, const vcgext::WorkingStartResult& ws, int workingFaces, StageTimes& times) {
  if (ws.firstStartFaces > 0 && !ws.firstKept) {
    const std::string what = ws.firstPatches > 0 ? " gave " + std::to_string(ws.firstPatches) + " patches and was not kept ("
                                                 : " was not used (";
    ctx.log("Fitmap Quad Simplification: the first start (" + std::to_string(ws.firstStartFaces) + " triangles)" + what +
            ws.fallbackReason + "): simplified from the working resolution (" + std::to_string(workingFaces) +
            " triangles)");
    times.push_back({"first_start", ws.firstSeconds});
  } else if (ws.firstKept) {
    ctx.log("Fitmap Quad Simplification: kept the cage of the first start (" + std::to_string(ws.firstStartFaces) +
            " triangles: the input is denser than the working resolution; docs/multires.md \"A coarser first start\")");
  }
  ctx.Value("first_start_faces", ws.firstStartFaces);
  ctx.Value("first_start_kept", ws.firstKept ? 1 : 0);
  for (const std::string& warning : ws.start.warnings) ctx.log("Warning: Fitmap Quad Simplification: " + warning);
  for (const std::string& note : ws.start.notes) ctx.log("Fitmap Quad Simplification: " + note);
  if (ws.start.work.decimated) times.push_back({"working_resolution", ws.start.work.seconds});
}
}  // namespace

bool ApplyQuad(GlueContext& ctx) {
  MeshModel& in = *ctx.md.mm();
  const auto t0 = std::chrono::steady_clock::now();
  vcgext::QuadSimplifyParams p;
  double tau = 0;
  int workingFaces = 0, firstFaces = 0;
  double closeHolesPct = 0;
  if (!QuadParams(ctx, p, tau, workingFaces, firstFaces, closeHolesPct)) return false;
  if (p.layoutTrials > 1 && !vcgext::BudgetLayout(p))
    ctx.log("Warning: Fitmap Quad Simplification: layout trials need a target patch count (and the equalized "
            "layout): one layout");

  const std::string memErr = vcgext::CheckPipelineMemory(vcgext::PipelineStep::Simplification, in.cm.fn, p.maxMemoryMb);
  if (!memErr.empty()) return ctx.Fail("Fitmap Quad Simplification: " + memErr);

  // The layer's working copy (input_prep.h); a pure-quad layer is simplified from its quads.
  vcgext::WorkingCopy w = vcgext::PrepareQuadPipelineCopy(in.cm);
  if (!w.error.empty()) return ctx.Fail("Fitmap Quad Simplification: " + w.error);
  for (const auto& n : w.notes) ctx.log("Fitmap Quad Simplification: " + n);
  for (const auto& n : w.warnings) ctx.log("Warning: Fitmap Quad Simplification: " + n);
  ctx.Value("crack_vertices", w.crackVertices);
  ctx.Value("staircase_step_edges", w.staircaseStepEdges);
  WarnIfNotSimilarity(ctx, in, "Fitmap Quad Simplification");
  const vcgext::TriData& tri = w.mesh;
  vcgext::QuadData given;
  const bool useQuads = LayerQuads(ctx, in, w, p.targetPatches, given);
  if (!useQuads) CloseHolesForLayout(ctx, w, closeHolesPct);
  vcgext::EmbreeScene scene(tri);
  if (!scene.Ok()) return ctx.Fail(scene.Error());

  // Fitmaps: from the layer if computed with this tau, else computed here (layer untouched).
  std::vector<double> S, M;
  StageTimes times;
  bool have = false;
  if (!QuadFitmaps(ctx, in, w, scene, tau, S, M, times, have)) return false;

  // Working resolution M' (§4): the control mesh starts from a decimated copy of a dense input.
  vcgext::StartMeshParams sp{0, 0, 0, 0};  // a pure-quad layer: from its quads
  if (!useQuads) sp = BudgetStartParams(workingFaces, p.targetPatches, int(tri.F.size()));
  vcgext::WorkingStartResult ws = vcgext::SimplifyFromWorkingStart(tri, scene, S, M, p, sp, useQuads ? 0 : firstFaces,
                                                                   ctx.cb, useQuads ? &given.F : nullptr);
  LogWorkingStart(ctx, ws, workingFaces, times);
  vcgext::QuadSimplifyResult& r = ws.result;
  if (!r.error.empty()) return ctx.Fail("Fitmap Quad Simplification: " + r.error);

  char name[128];
  snprintf(name, sizeof name, "%s quads tau=%g%%", in.label().toStdString().c_str(), tau);
  MeshModel* out = ctx.md.addNewMesh("", name, true);
  out->cm.Tr = in.cm.Tr;
  out->updateDataMask(MeshModel::MM_POLYGONAL);
  vcgext::ExportQuads(r.quads, out->cm);
  UpdateBoxAndNormals(*out);
  if (r.countPatches > 0) times.push_back({"count_pass", r.secondsCount});
  times.push_back({"tri_to_quad", r.secondsTriToQuad});
  times.push_back({"initial_fit", r.secondsInitialFit});
  times.push_back({"simplification", r.secondsSimplify});
  if (r.secondsLayoutTrials > 0) times.push_back({"layout_trials", r.secondsLayoutTrials});
  if (r.secondsBudgetRetries > 0) times.push_back({"budget_retries", r.secondsBudgetRetries});
  if (r.secondsStartRetries > 0) times.push_back({"start_refinement", r.secondsStartRetries});
  if (r.secondsRescue > 0) times.push_back({"rescue_by_budget", r.secondsRescue});
  if (r.secondsFittedCoverage > 0) times.push_back({"fitted_coverage", r.secondsFittedCoverage});
  SetStageTimes(out->cm, times);
  StageMemory memory = have ? GetStageMemory(in.cm) : StageMemory{};
  memory.push_back({"quad_simplification", vcgext::StagePeakMemoryMb()});
  SetStageMemory(out->cm, memory);

  ReportQuads(ctx, r, p, tri, scene, t0);
  return true;
}

}  // namespace fitmapquad
