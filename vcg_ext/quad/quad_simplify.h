#pragma once
/// \file quad_simplify.h
/// Fitmap-driven quad simplification (Panozzo et al. 2011, §3.2–3.4): turns a triangle mesh M
/// into a coarse, adaptive, pure-quad Catmull-Clark control mesh K whose limit surface follows M.
///
///  1. tri-to-quad on the same vertices (§3.2, tri_to_quad.h), or the caller's quads as they are;
///  2. control points solved so that the limit surface interpolates the input vertices,
///     L V_K = V_M (§3.2, cc_limit.h);
///  3. priority queue of diagonal collapses, cost |d| F_S(phi(c)) (d the diagonal between the
///     limit points of its corners, c the limit point at the patch centre, phi its projection
///     onto M along the limit normal, F_S interpolated barycentrically at the hit); a collapse
///     is feasible only if every patch it enlarges keeps its diameter (max distance centre-corner)
///     within F_M at its centre (§3.3; the paper's sentence states the opposite inequality, its
///     intent is this one); after each collapse immediate doublet removal and edge swaps in the
///     1-ring that strictly lower sum |valence - regular| over the 6 hexagon vertices;
///  4. local fit after each step (§3.4) on W = affected vertices + their 1-ring, twice:
///     tangential smoothing (halfway to the mean of incident face centroids), then re-interpolation
///     of the projections of the limit points onto M (local solve of (1), others frozen);
///  5. a step is undone if it would break manifoldness/topology (QuadMesh operators) or flip a
///     patch against the input (limit normal at the patch centre vs input normal at the hit).
/// Halts when no feasible collapse is left or at `targetPatches`; by default (Layout::Equalized)
/// the count of that halting is measured in a first pass and spent on an S-fitmap layout.
#include <array>
#include <map>
#include <string>
#include <vector>

#include <cstring>  // wrap/callback.h uses strcpy without including it
#include <wrap/callback.h>
#include <vcg/complex/complex.h>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/far_spikes.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/pipeline_memory.h"
#include "vcg_ext/quad/tri_to_quad.h"

namespace vcgext {

/// The swap sweep's guard (QuadSimplifyParams::sweepRmsTolerance): how much more of the input's
/// area (percentage points) the swept cage's fitted limit may leave unprojectable than the unswept
/// one's: 0.01, the measure's noise between cages of the same quality (triceratops @ 400: 0.09 ->
/// 0.20 % with the sweep is refused).
inline constexpr double kSweepUnprojectableSlackPct = 0.01;

/// Parameters of SimplifyToQuads. There is no tau here: the M-Fitmap already encodes it.
struct QuadSimplifyParams {
  int targetPatches = 0;          ///< stop at this many patches (0 = only when no feasible collapse is left)
  /// The vcg entry point refuses (an error) a mesh whose simplification would need more memory
  /// than this many MB (EstimatePipelineMemoryMb); 0: 80 % of the memory available when it starts.
  double maxMemoryMb = 0;
  bool useMFitmap = true;         ///< the projectability test of §3.3 (false: S-cost only, needs targetPatches)
  bool edgeSwaps = true;          ///< valence-improving swaps after each collapse (§3.3.2)
  /// Beyond the paper (issue 13, docs/quad.md "Swap sweep"): after the last collapse, passes over
  /// the whole cage apply every chain of at most this many edge swaps (neutral ones moving a
  /// singularity, the last lowering the summed valence defect: a pair of singularities brought
  /// together and cancelled), each chain checked like a step (local fit, flip test, guard);
  /// 1 = only swaps that lower the defect by themselves; 0 = off, the default (the paper: swaps
  /// only in the 1-ring of each collapse's survivor; 3 cuts the irregular vertices by a fifth to a
  /// third but moves the limit error and the unprojectable area up a little on average).
  int swapSweepChain = 0;
  /// The sweep's guard (docs/quad.md "Swap sweep"): when the sweep kept chains, both cages are
  /// fitted and measured as the pipeline's report will measure them (RMS limit error and
  /// unprojectable share of the fitted limit; two fits); the swept cage is kept only when its
  /// RMS limit error is at most this fraction above the unswept one's and its unprojectable share
  /// at most kSweepUnprojectableSlackPct above. Negative: no guard (the sweep's cage is kept).
  double sweepRmsTolerance = 0.02;
  int fitRounds = 2;              ///< smoothing + re-interpolation rounds per step (paper: 2)
  double smoothingWeight = 0.5;   ///< move this fraction towards the mean of incident centroids (paper: 1/2)
  double solveTolPercent = 1e-5;  ///< interpolation solve tolerance, % of the bbox diagonal (absolute residual)
  int localSolveIterations = 30;  ///< max Gauss-Seidel sweeps of the local solve
  double projectionPercent = 10.0;  ///< max ray length of the projection phi, % of the bbox diagonal
  double boundaryCornerAngleDeg = 45;  ///< remove one-face boundary vertices where the boundary turns less than this (0 = never)
  /// Geometric guard (beyond the paper, keeps thin parts): after the local fit of a step, the
  /// limit surface of every patch touching the moved vertices is sampled at its centre and its
  /// edge midpoints; each sample must project (along its limit normal) onto the input with an
  /// agreeing normal within deviationFactor * F_M(hit) (F_M interpolated at the hit), else the
  /// step is undone. 0 = off (the paper's behaviour).
  double deviationFactor = 0.25;
  /// optional absolute cap of that tolerance, % of the bbox diagonal (0 = no cap)
  double maxDeviationPercent = 0.0;
  bool finalReinterpolation = true;  ///< one global solve at the end: all limit vertices back onto the input
  /// Under a budget, the budget ladder's retries when the first pass stops above it (docs/quad.md
  /// "Budget ladder"); false: the first pass as it is.
  bool budgetLadder = true;
  bool validateEveryOperation = false;  ///< test mode: full validity check after every step (O(F) each)
  /// How the patches are spent when the count is the paper's (targetPatches 0, M-fitmap test on).
  /// Beyond the paper (docs/quad.md "Layout"): the paper's halting keeps collapsing until the
  /// M-fitmap blocks every collapse, so patch sizes follow M (projectability) and not S (error):
  /// huge patches where M is loose, and the RMS limit error of one layout differs by 1.5x from
  /// that of a start mesh 5 % coarser (bunny00: 1.70 to 2.62 per mille). Equalized runs the
  /// paper's halting on a coarse start mesh (countFaces) only to count its patches N, then
  /// simplifies the real start mesh in S-cost order without the M test down to N patches (the
  /// thin-part guard still holds): the same count, patches sized by the S-fitmap. With a
  /// targetPatches budget, Equalized is the layout pass alone (no M test): the budget is reached
  /// whatever tau (the M test used to halt above it).
  enum class Layout {
    Equalized,     ///< the paper's count, S-fitmap layout (default)
    PaperHalting,  ///< the paper literally: collapse until no feasible collapse is left
  } layout = Layout::Equalized;
  /// Equalized, no budget: coverage guard (issue 16, docs/robustness.md "Closed thin shapes").
  /// When the chosen cage's interpolating limit stays farther than this from the input (RMS of
  /// the input vertices' distances, 1/1000 of the bbox diagonal) the M-fitmap did not stop the
  /// collapses (a thin closed part whose M is loose: a capped cylinder's cage shrank to one end),
  /// and the layout pass runs again with twice the patches, up to 8 times, until it is within.
  /// The filter sets 5 tau (at most 100): scans sit far below at tau = 1 % (bunny00 ~3,
  /// nefertiti's 17-patch cage 23); smooth limits of sharp CAD solids above (cube.off 134:
  /// a 16-patch cage 2.4 tau off after the fit). 0 = off.
  double coverageRmsPermille = 50;
  /// The guard's second trigger: the share of the input's area (%) lying wholly beyond the
  /// outline of the interpolating limit (triangles whose sample points' closest limit points are
  /// on the limit's boundary and off its normal: no normal line reaches them; <= 20k triangles
  /// tested). Catches flat and open shapes whose M never stops the collapses while the RMS stays
  /// low: the corpus disk's 5-patch cage leaves 9.9 % (docs/robustness.md "Flat and open
  /// shapes"). Half the report's 1 % warning level. When it fires alone (the RMS within) and
  /// the fitted checks are on (coverageFittedPct > 0), the cage is fitted first and kept if its
  /// fitted limit, measured as the report will, leaves no more than this share unreached (a holed
  /// scan: hole rims the fit reaches); otherwise each relayout is judged on its fitted limit and
  /// grows the patches by the excess squared, 1.25x to 2x (docs/quad.md "Coverage judged after
  /// the fit"). 0 = off.
  double coverageUnprojectablePct = 0.5;
  /// Equalized, no budget: a cage that keeps more than half of its start mesh's quads (the
  /// start's resolution, not the Fitmaps, decided it) or that the coverage guard could not
  /// enlarge, and whose interpolating limit stays farther than this from the input (RMS, 1/1000
  /// of the bbox diagonal), is simplified again from its start refined at edge midpoints
  /// (SimplifyToQuads; docs/quad.md "A start too coarse"). The filter sets 10 tau (tau itself);
  /// 0 = off.
  double startRmsPermille = 10;
  /// Equalized, no budget: a cage whose limit, fitted, still stays farther than this from the
  /// input (RMS, 1/1000 of the bbox diagonal) after the guards and the start refinement is laid
  /// out again under a budget of its own patch count, and that cage kept when, fitted, it is
  /// closer (SimplifyToQuads; docs/quad.md "A cage far off"). The filter sets 10 tau; 0 = off.
  double rescueRmsPermille = 10;
  /// Equalized, no budget, after the rescue: a cage whose interpolating limit stays farther than
  /// rescueRmsPermille from the input (the trigger that spares the fit on most meshes) and whose
  /// fitted limit, measured as the report will, leaves more than this share (%) of the input's
  /// area unreached by projection is laid out again under budgets of 2, 4 and 8 times its patches
  /// while the share stays above; a relayout is kept when it leaves less unreached than the best
  /// so far and its fitted limit is no farther (RMS). The report warns above 1 %, the default: a sphere with 30
  /// small holes, 3.3 % unreached at the paper's 119 patches (docs/quad.md "Unreached after the
  /// fit"). 0 = off.
  double coverageFittedPct = 1.0;
  /// Equalized: the count pass starts from the start mesh decimated to this many triangles
  /// (larger start meshes only; the count moves by ~2 % between 10k and 40k on bunny00).
  int countFaces = 10000;
  /// Equalized, two threads: a count the coarse start bounds (above countFaces / 16) is counted
  /// again on the real start mesh beside the layout pass, which goes on down to this many times
  /// the coarse count (or stops where it is, if already lower) and from there follows the
  /// recount's live count; a recount above a step the layout pass took redoes the layout pass
  /// after it. The cage does not depend on it, only the time (docs/quad.md "Layout").
  int recountFloorFactor = 2;
  /// Regularity (issue 13, docs/quad.md "Regularity"): in the equalized layout pass (and under
  /// a budget) a collapse's S cost is multiplied by (1 + valenceWeight)^d, d the change of the
  /// summed valence defect |valence - regular| of the collapsed face's four corners (regular: 4
  /// faces inside, 2 on the boundary), so collapses that make or keep irregular vertices wait.
  /// Not in the paper's halting (Layout::PaperHalting, and the equalized layout's count pass),
  /// which keeps the paper's cost. 0 = off (default: a trade, not a gain — 20-60 % fewer
  /// irregular vertices, RMS limit error from -40 % to +80 % by mesh; docs/quad.md "Regularity").
  double valenceWeight = 0;
  /// Layout trials under a budget (targetPatches > 0; issue 13, docs/quad.md "Layout trials"):
  /// the layout pass (and its budget ladder) runs with this many valence weights — valenceWeight first, then the first
  /// others of kTrialValenceWeights (0, 0.25, 1, 0.05) — and keeps the cage that reaches the
  /// budget (else comes closest to it) with the lowest RMS distance from the input's vertices to
  /// its fitted limit (FitCatmullClark with default parameters, as the next filter fits it),
  /// among the trials with no more flipped patches and vertices than the first. The error of one
  /// layout moves by +-25 % with tiny changes of the collapse order (docs/quad.md "Regularity"),
  /// so the best of several is a lower error for the time of several passes. 1 = one pass.
  int layoutTrials = 1;
  /// Threads for a step's checks and projections (OpenMP's maximum when parallel): chosen from
  /// measured speed (AdaptiveParallelism, default), never, or always (tests). Same result.
  /// Never also runs the equalized layout's count pass before its layout pass instead of beside
  /// it (docs/quad.md "Layout").
  enum class ParallelChecks { Adaptive, Never, Always } parallelChecks = ParallelChecks::Adaptive;
  quad::TriToQuadParams triToQuad;
};

/// Chooses, block by block, whether a simplification step's checks and projections run on
/// several threads (beyond the paper; docs/quad.md "Limitations"). On idle cores the parallel checks
/// save ~25 %, but one fork/join per step collapses when another process holds a core (bunny00:
/// 23 s instead of 7 s with one busy core, 74 s instead of 10 s with two). The choice follows
/// measured time per step (blocks of steps vary in cost, hence the margins): a probe of the other
/// mode after `probe` blocks switches only if it is 15 % faster, and each probe that does not
/// doubles that interval (minProbe .. maxProbe); the current mode is left at once when it is
/// 1.5x slower than the other's latest figure (the load changed). It starts serial, and the
/// parallel mode runs in short blocks (probes shorter still), since it is the one that can be
/// very slow; a parallel probe that wins must be confirmed by the next regular block. The
/// simplification's result never depends on the mode.
class AdaptiveParallelism {
 public:
  explicit AdaptiveParallelism(bool allowed, int serialSteps = 128, int parallelSteps = 64, int probeSteps = 16,
                               int minProbe = 4, int maxProbe = 256)
      : allowed_(allowed), serialSteps_(serialSteps), parallelSteps_(parallelSteps), probeSteps_(probeSteps),
        probe_(minProbe), minProbe_(minProbe), maxProbe_(maxProbe) {}
  bool Parallel() const { return par_; }
  /// Steps in the current block: serial blocks are long (steady figures), parallel ones short
  /// (a wrong choice costs little), parallel probes shorter still.
  int BlockSteps() const { return !par_ ? serialSteps_ : probing_ ? probeSteps_ : parallelSteps_; }
  /// Ends a block that took `secondsPerUnit` in the current mode (time per unit of work: steps
  /// vary in size, so the caller divides by a work measure); returns the next block's mode.
  bool EndBlock(double secondsPerUnit);
  int Switches() const { return switches_; }
  int ParallelBlocks() const { return parallelBlocks_; }
  int Blocks() const { return blocks_; }

 private:
  void Switch(bool probe);
  bool allowed_, par_ = false;
  int serialSteps_, parallelSteps_, probeSteps_;
  double last_[2] = {-1, -1};  ///< latest seconds per step: [serial, parallel]
  int probe_, minProbe_, maxProbe_, sinceProbe_ = 0;
  bool probing_ = false, confirming_ = false;
  int switches_ = 0, parallelBlocks_ = 0, blocks_ = 0;
};

/// Outcome and statistics. `error` non-empty: nothing else is meaningful. `message` carries
/// non-fatal notes (e.g. "too small to simplify").
struct QuadSimplifyResult {
  std::string error;
  std::string message;
  QuadData quads;                 ///< the control mesh K (counter-clockwise quads)
  quad::TriToQuadPath triToQuadPath = quad::TriToQuadPath::Pairing;
  int initialPatches = 0;
  int patches = 0;
  int countPatches = 0;            ///< Layout::Equalized: the paper's halting count (0: no count pass)
  int countStartFaces = 0;         ///< Layout::Equalized: triangles of the count pass's start mesh
  /// Layout::Equalized: wall time the count pass added (in secondsTotal); when the count pass's
  /// cage is kept (keptPaperLayout), the time the other passes added, beside it or after it
  double secondsCount = 0;
  /// Layout::Equalized: seconds of the count pass that ran beside the layout pass on a second
  /// thread (not in secondsTotal; its whole time is secondsCount + this)
  double secondsCountOverlapped = 0;
  /// Layout::Equalized when the count pass ran on the start mesh itself (small start meshes, or a
  /// count too high for the coarse one): that pass is the paper's own result, and the cage kept is
  /// the one whose interpolating limit is closer to the input (RMS, absolute; 0 = not compared).
  double paperLayoutRms = 0, equalizedLayoutRms = 0, layoutRms = 0;
  bool keptPaperLayout = false;    ///< that comparison kept the paper's halting result
  /// Coverage guard (QuadSimplifyParams::coverageRmsPermille): layout passes it added (0: none),
  /// and the patches and interpolating-limit RMS (absolute) of the cage it replaced.
  int coverageRelayouts = 0;
  int coverageFromPatches = 0;
  double coverageFromRms = 0;
  double coverageFromUnprojectablePct = 0;  ///< that cage's unprojectable share (%)
  double layoutUnprojectablePct = -1;       ///< the kept cage's (guard on; -1: not measured)
  /// The area trigger alone fired and the cage was fitted: the fitted limit's unreached share (%)
  /// as the report measures it; at most coverageUnprojectablePct: the cage was kept (-1: no fit).
  double coverageFittedCheckPct = -1;
  /// That fit left more: the cage the guard laid out again, fitted, leaves this share (%) (-1: the
  /// guard judged the interpolating limit, or did not lay out again).
  double layoutFittedUnprojectablePct = -1;
  /// The coverage guard still fired on the kept cage and could not double its patches (half the
  /// start's quads): the start bounds it.
  bool coverageOutOfRoom = false;
  /// The start was refined at edge midpoints this many times (startRmsPermille; SimplifyToQuads),
  /// and the patches of the coarser start's cage (0: not refined).
  int startRefinements = 0;
  int startRefinedFrom = 0;
  double secondsStartRetries = 0;  ///< the passes from the coarser start(s) (kept or not), in secondsTotal
  /// rescueRmsPermille: the far cage's patches and fitted RMS (absolute) when the budget's cage
  /// replaced it (0: no rescue kept), and the seconds the check and the budget's pass took
  /// (in secondsTotal; 0: the interpolating limit was near, no check).
  int rescuedFromPatches = 0;
  double rescuedFromRms = 0;
  double secondsRescue = 0;
  /// coverageFittedPct: the budgeted relayouts kept (0: none), the patches and fitted unreached
  /// share (%) of the cage they replaced, the kept cage's share (-1: not measured), and the
  /// seconds of the check and its passes (in secondsTotal).
  int fittedCoverageRelayouts = 0;
  int fittedCoverageFromPatches = 0;
  double fittedCoverageFromPct = 0;
  double fittedUnprojectablePct = -1;
  double secondsFittedCoverage = 0;
  /// Budget (targetPatches) the thin-part guard stopped above (the ladder, docs/quad.md "Budget
  /// ladder"): which retry the kept cage is — 1: the guard's tolerance doubled; 2: a start
  /// decimated to 4 x the budget in triangles (budgetStartFaces); 3: that start, the tolerance
  /// doubled; 4: a start of 2.5 x the budget in triangles, the tolerance doubled —, its guard
  /// factor (deviationFactor), and the patches the first pass stopped at.
  /// 0 / -1 / 0 / 0: the first pass's cage.
  int budgetRelaxations = 0;
  double budgetDeviationFactor = -1;
  int budgetFromPatches = 0;
  int budgetStartFaces = 0;
  double secondsBudgetRetries = 0;  ///< the ladder's passes not kept (the first pass's too), in secondsTotal
  /// The rungs the ladder ran, in order (e.g. "1234", "234": rung 1 runs after the coarse starts
  /// when the first pass stopped above kFarAboveBudget x the budget, and not when one of them
  /// reached it); empty: no ladder.
  std::string budgetRungsRun;
  /// Layout trials (layoutTrials > 1): the valence weight of the kept trial, how many ran, and
  /// the time of those not kept (in secondsTotal).
  double trialValenceWeight = -1;
  int layoutTrialsRun = 0;
  /// per trial: its weight, patches and fitted RMS distance (per mille of the diagonal; "-" when it
  /// missed the budget), e.g. "0: 1000 patches, 1.031; 0.25: 1000 patches, 1.002"
  std::string layoutTrialsSummary;
  double secondsLayoutTrials = 0;
  int irregularVertices = 0;
  std::vector<int> valenceHistogram;  ///< index = valence
  int collapses = 0, swaps = 0, doublets = 0;
  int sweepSwaps = 0;  ///< swap chains kept by the final sweep (swapSweepChain)
  /// The sweep's guard (sweepRmsTolerance), when it ran: the chains of a refused sweep (then
  /// sweepSwaps is 0 and the cage is the unswept one), both cages' RMS limit error (absolute) and
  /// unprojectable share (%) as the report measures them, and its time (in secondsTotal).
  int sweepRefusedChains = 0;
  bool sweepGuarded = false;
  double sweepUnsweptRms = 0, sweepSweptRms = 0, sweepUnsweptUnprojectablePct = 0, sweepSweptUnprojectablePct = 0;
  double secondsSweepGuard = 0;
  int boundaryCorners = 0;        ///< boundary corner removals (open boundaries)
  int rejectedByM = 0;            ///< collapses refused by the M-fitmap test
  int rejectedTopology = 0;       ///< refused by the operators (link condition, boundary, valence)
  int rejectedFlip = 0;           ///< undone because a patch flipped against the input / left it
  int rejectedDeviation = 0;      ///< undone by the geometric guard (limit samples too far from the input)
  double parallelStepShare = 0;   ///< share of the steps whose checks ran on several threads (AdaptiveParallelism)
  int flippedPatches = 0;         ///< final patches whose centre normal disagrees with the input (or miss it)
  int flippedVertices = 0;        ///< final interior vertices whose limit normal disagrees likewise
  int initialFlippedPatches = 0;  ///< the same counts on the initial interpolating mesh (noisy scans)
  int initialFlippedVertices = 0;
  double initialSolveResidual = 0;  ///< max |limit - input vertex| after the global solve (absolute)
  int initialSolveIterations = 0;
  double secondsTriToQuad = 0, secondsInitialFit = 0, secondsSimplify = 0, secondsTotal = 0;
};

/// Whether a cage of `patches` meets a budget of `target` patches (QuadSimplifyParams::
/// targetPatches > 0): at most 2 % above it (one step removes a face and a few doublets). The
/// budget ladder, the start refinement under a budget and the filter's warning all judge by it.
inline bool BudgetReached(int patches, int target) { return patches <= target + target / 50; }

/// Whether a count of `patches` (the paper's halting) from a start of `startFaces` triangles is
/// bounded by that start's resolution: above startFaces / 16, its quads reduced less than 8x
/// (man.off counted 2 232 patches from 10k triangles, 2 940 from its own 35k). The equalized
/// layout counts again on the real start by it; a dense input's first start falls back by it
/// (working_start.h).
inline bool CountBoundedByStart(int patches, long startFaces) { return 16L * patches > startFaces; }

/// Whether `p` asks for a budget's layout: the equalized layout with targetPatches > 0. Only
/// there do the budget ladder and the layout trials run (SimplifyToQuads' dispatch); the filter
/// warns by the same rule when layout trials are asked for without it.
inline bool BudgetLayout(const QuadSimplifyParams& p) {
  return p.layout == QuadSimplifyParams::Layout::Equalized && p.targetPatches > 0;
}

/// Layout trials (QuadSimplifyParams::layoutTrials, docs/quad.md "Layout trials"): the valence
/// weights tried after the user's own, in this order.
inline constexpr double kTrialValenceWeights[] = {0, 0.25, 1, 0.05};
/// The weights of `trials` layout trials: `first` (the user's valenceWeight), then the first of
/// kTrialValenceWeights other than it (at most 1 + 4).
std::vector<double> TrialValenceWeights(double first, int trials);

/// Simplifies triangle mesh `input` into a pure-quad Catmull-Clark control mesh (§3.2–3.4).
/// \param input  manifold, consistently oriented triangle mesh (double arrays)
/// \param scene  Embree scene built on `input` (projection phi)
/// \param S, M   per-input-vertex S-fitmap (1/length) and M-fitmap (absolute radius), as from
///               vcgext::ComputeFitmaps; sizes must equal input.V.size()
/// \param initialQuads  optional: quads on input.V to start from (a layer that is already quads);
///               nullptr = tri-to-quad conversion
/// \param startMesh optional: the working resolution M' (§4, decimate.h) the control mesh starts
///               from (tri-to-quad and the initial interpolation use its vertices); every
///               projection, the M-fitmap test and the S cost still refer to `input` (M).
///               nullptr = `input` itself. Not together with initialQuads.
/// Beyond the paper (docs/quad.md): with a budget (targetPatches) the layout pass alone and, when
/// the guards stop it above the budget, the budget ladder (a looser guard, starts decimated to
/// 4 and 2.5 x the budget, each retry judged by its fitted limit); without one, the paper's count
/// laid out by the S-fitmap (Layout::Equalized) and the coverage guard; with or without one, a
/// start too coarse for the input refined at edge midpoints (startRmsPermille; under a budget only
/// when it was missed and the cage, fitted, stays that far off); last, on the chosen cage, the
/// swap sweep (swapSweepChain, off by default: docs/quad.md "Swap sweep").
/// Errors: empty input, size mismatches, non-finite fitmaps, non-manifold input (reports the
/// number of non-manifold edges and vertices). A mesh too small to simplify returns its pure-quad
/// mesh with `message` set. Cost: roughly O(F log F) collapses, each O(1) local work
/// (a few hundred ray casts and small solves).
QuadSimplifyResult SimplifyToQuads(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
                                   const std::vector<double>& M, const QuadSimplifyParams& params,
                                   vcg::CallBackPos* cb = nullptr, const std::vector<Quad>* initialQuads = nullptr,
                                   const TriData* startMesh = nullptr);

/// Quads encoded in a vcg triangle layer the MeshLab way (triangle pairs whose shared edge is
/// faux), indexed like the TriData that ImportTriangles(m, data, true) produces. Returns false
/// (and leaves `quads` empty) if the faux edges do not pair every live triangle into a quad.
template <class MeshType>
bool PolygonalQuads(const MeshType& m, const TriData& data, std::vector<Quad>& quads);

/// vcg entry point: reads the per-vertex float attributes `sAttr` / `mAttr` (as written by
/// vcgext::ComputeFitmaps: "FitmapS", "FitmapM"; this library does not compute them), builds the
/// Embree scene and simplifies. A polygonal layer whose faux edges pair all triangles into quads
/// is simplified as quads (path AlreadyQuads), any other layer goes through tri-to-quad. The
/// input mesh is not modified. Errors as SimplifyToQuads, plus missing attributes and a mesh too
/// large for the memory (QuadSimplifyParams::maxMemoryMb).
template <class MeshType>
QuadSimplifyResult SimplifyToQuads(const MeshType& m, const QuadSimplifyParams& p, vcg::CallBackPos* cb = nullptr,
                                   const char* sAttr = "FitmapS", const char* mAttr = "FitmapM");

/// Counts non-manifold edges (more than two faces or inconsistent orientation) and non-manifold
/// vertices (fan not a single disk/half-disk) of a triangle mesh. `where` (optional) receives the
/// non-manifold vertices and the non-manifold edges' ends (unsorted, possibly repeated).
void CountNonManifold(const TriData& m, int* nonManifoldEdges, int* nonManifoldVertices,
                      std::vector<int>* where = nullptr);

// ---------------------------------------------------------------------------- templates
template <class MeshType>
bool PolygonalQuads(const MeshType& m, const TriData& data, std::vector<Quad>& quads) {
  quads.clear();
  // faux flags per imported triangle (same traversal and filtering as ImportTriangles)
  std::vector<std::array<bool, 3>> faux;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    const auto* v0 = f.cV(0); const auto* v1 = f.cV(1); const auto* v2 = f.cV(2);
    if (v0 == v1 || v1 == v2 || v0 == v2) continue;
    faux.push_back({f.IsF(0), f.IsF(1), f.IsF(2)});
  }
  if (faux.size() != data.F.size()) return false;
  std::map<std::pair<int, int>, std::pair<int, int>> he;  // directed edge -> (triangle, corner)
  for (size_t t = 0; t < data.F.size(); ++t)
    for (int k = 0; k < 3; ++k) he[{data.F[t][k], data.F[t][(k + 1) % 3]}] = {int(t), k};
  std::vector<char> used(data.F.size(), 0);
  for (size_t t = 0; t < data.F.size(); ++t) {
    int nf = int(faux[t][0]) + int(faux[t][1]) + int(faux[t][2]);
    if (nf != 1) { quads.clear(); return false; }
    if (used[t]) continue;
    int k = faux[t][0] ? 0 : faux[t][1] ? 1 : 2;
    int a = data.F[t][k], b = data.F[t][(k + 1) % 3], c = data.F[t][(k + 2) % 3];
    auto it = he.find({b, a});
    if (it == he.end()) { quads.clear(); return false; }
    int u = it->second.first, ku = it->second.second;
    if (used[u] || !faux[u][ku]) { quads.clear(); return false; }
    int d = data.F[u][(ku + 2) % 3];
    quads.push_back({a, d, b, c});
    used[t] = used[u] = 1;
  }
  return true;
}

template <class MeshType>
QuadSimplifyResult SimplifyToQuads(const MeshType& m, const QuadSimplifyParams& p, vcg::CallBackPos* cb,
                                   const char* sAttr, const char* mAttr) {
  QuadSimplifyResult res;
  res.error = CheckPipelineMemory(PipelineStep::Simplification, m.fn, p.maxMemoryMb);
  if (!res.error.empty()) return res;
  WorkingCopy w = PrepareQuadPipelineCopy(m);
  if (!w.error.empty()) { res.error = w.error; return res; }
  MeshType& mm = const_cast<MeshType&>(m);  // attribute lookup is non-const in vcglib; nothing is written
  auto hS = vcg::tri::Allocator<MeshType>::template FindPerVertexAttribute<float>(mm, sAttr);
  auto hM = vcg::tri::Allocator<MeshType>::template FindPerVertexAttribute<float>(mm, mAttr);
  if (!vcg::tri::Allocator<MeshType>::template IsValidHandle<float>(mm, hS) ||
      !vcg::tri::Allocator<MeshType>::template IsValidHandle<float>(mm, hM)) {
    res.error = std::string("the layer has no Fitmaps (per-vertex attributes ") + sAttr + " / " + mAttr +
                "): compute the Fitmaps first";
    return res;
  }
  const std::vector<double> S = AttributeOnWorkingCopy(w, m, hS), M = AttributeOnWorkingCopy(w, m, hM);
  TriData raw;
  ImportTriangles(m, raw, /*allowPolygonal=*/true);
  std::vector<Quad> quads;
  bool polygonal = PolygonalQuads(m, raw, quads) && RemapQuadsToWorkingCopy(w, quads);
  EmbreeScene scene(w.mesh);
  if (!scene.Ok()) { res.error = scene.Error(); return res; }
  return SimplifyToQuads(w.mesh, scene, S, M, p, cb, polygonal ? &quads : nullptr);
}

}  // namespace vcgext
