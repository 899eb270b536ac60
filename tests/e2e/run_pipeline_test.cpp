// meshlab_scripts/run_pipeline.sh end to end on a real scan (set-up skipped: ctest runs after it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "e2e_support.h"
#include "test_support.h"
#include "vcg_ext/io/mesh_io.h"

namespace {

std::string Pipeline() { return e2e::Q(e2e::Script("run_pipeline.sh")); }
// run_pipeline.sh `args` on data-set mesh `mesh` into `outdir` (the existing build and install)
e2e::RunResult RunOnSample(const std::string& args, const std::string& mesh, const std::string& outdir) {
  return e2e::Run("FITMAP_SKIP_SETUP=1 " + Pipeline() + " " + args + " " + e2e::Q(testsupport::SamplePath(mesh)) +
                  " " + e2e::Q(outdir));
}

// The same into e2e::OutPath(`name`), with the run's report.json and meshlab.log
struct PipelineOutputs {
  e2e::RunResult run;
  std::string json, log;
};
PipelineOutputs RunForReport(const std::string& args, const std::string& mesh, const std::string& name) {
  const std::string outdir = e2e::OutPath(name);
  PipelineOutputs o{RunOnSample(args, mesh, outdir), "", ""};
  o.json = e2e::Slurp(outdir + "/report.json");
  o.log = e2e::Slurp(outdir + "/meshlab.log");
  return o;
}

// The budget ladder reached `target` patches (within 2 %, no budget warning) from a start
// decimated to `faces` triangles.
void ExpectBudgetReachedFromDecimatedStart(const PipelineOutputs& o, int target, int faces) {
  EXPECT_NE(o.log.find("from a start decimated to " + std::to_string(faces) + " triangles"), std::string::npos) << o.log;
  EXPECT_EQ(o.log.find("was not reached"), std::string::npos) << "no budget warning";
  EXPECT_NEAR(e2e::JsonNumber(o.json, "patches"), target, target / 50) << o.json;
}

TEST(RunPipeline, WritesColourMappedFitmapOnElephant) {  // the first output, checked in detail
  const std::string outdir = e2e::OutPath("pipeline_elephant");
  auto r = RunOnSample("--tau 5", "elephant.off", outdir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  vcgext::TMesh m;
  ASSERT_EQ(vcgext::LoadMesh(outdir + "/fitmap.ply", m), "");
  EXPECT_EQ(m.vn, 2775);
  double sum = 0;
  for (const auto& v : m.vert) {
    ASSERT_TRUE(std::isfinite(v.cQ()));
    sum += v.cQ();
  }
  EXPECT_GT(sum, 0.0);
}

TEST(RunPipeline, RejectsBadArguments) {
  auto r = e2e::Run("FITMAP_SKIP_SETUP=1 " + Pipeline() + " --tau abc");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("--tau takes a number"), std::string::npos) << r.output;
  r = e2e::Run("FITMAP_SKIP_SETUP=1 " + Pipeline() + " --patches -3");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("--patches takes a whole number"), std::string::npos) << r.output;
  r = e2e::Run("FITMAP_SKIP_SETUP=1 " + Pipeline() + " --regularity -1");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find("--regularity takes a number"), std::string::npos) << r.output;
  r = e2e::Run("FITMAP_SKIP_SETUP=1 " + Pipeline() + " --trials 6");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find("--trials takes a whole number from 1 to 5"), std::string::npos) << r.output;
  r = e2e::Run("FITMAP_SKIP_SETUP=1 " + Pipeline() + " /nonexistent/mesh.off " + e2e::Q(e2e::OutPath("x")));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("input not found"), std::string::npos) << r.output;
}

// When MeshLab's own reader fails before any filter runs, the script, not the plugin, says what
// happened and what to do. A truncated OFF is refused every time; MeshLab 2020.09's crash on the
// data set's prim.off (comment lines among its data) comes and goes between runs, so it is not
// the test input (CI 2026-12-01: it read the file once and crashed on it in other runs).
TEST(RunPipeline, ReaderCrashIsNamed) {
  const std::string in = e2e::OutPath("truncated_input.off");
  {
    std::ofstream f(in);
    f << "OFF\n4 4 0\n0 0 0\n1 0 0\n";
  }
  auto r = e2e::Run("FITMAP_SKIP_SETUP=1 " + Pipeline() + " " + e2e::Q(in) + " " + e2e::Q(e2e::OutPath("reader_crash")));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("MeshLab could not read"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("re-save the mesh"), std::string::npos) << r.output;
}

// A scan too large for the memory (core/pipeline_memory.h) is refused by the filter that would
// exhaust it, with what to do, before it allocates: the kernel would otherwise kill MeshLab.
// FITMAP_MAX_MEMORY_MB stands in for a small machine: bunny00's Fitmaps are estimated at 92 MB,
// its simplification at 43, its fit at 123.
TEST(RunPipeline, ScanTooLargeForTheMemoryIsRefusedByTheFilterThatWouldExhaustIt) {
  const std::string bunny = e2e::Q(testsupport::SamplePath("bunny00.off"));
  auto fitmaps = e2e::Run("FITMAP_SKIP_SETUP=1 FITMAP_MAX_MEMORY_MB=60 " + Pipeline() + " " + bunny + " " +
                          e2e::Q(e2e::OutPath("memory_cap_60")));
  EXPECT_NE(fitmaps.exitCode, 0);
  EXPECT_NE(fitmaps.output.find("Compute Fitmaps: a layer of 75408 triangles would need about 92 MB of memory, more "
                                "than the 60 MB allowed: decimate the layer first"),
            std::string::npos)
      << fitmaps.output;
  auto fit = e2e::Run("FITMAP_SKIP_SETUP=1 FITMAP_MAX_MEMORY_MB=100 " + Pipeline() + " " + bunny + " " +
                      e2e::Q(e2e::OutPath("memory_cap_100")));
  EXPECT_NE(fit.exitCode, 0);
  EXPECT_EQ(fit.output.find("Compute Fitmaps: a layer"), std::string::npos) << "the Fitmaps fit in 100 MB";
  EXPECT_NE(fit.output.find("Fit Catmull-Clark Surface: a reference layer of 75408 triangles would need about 123 MB "
                            "of memory, more than the 100 MB allowed: decimate the reference layer first"),
            std::string::npos)
      << fit.output;
  EXPECT_FALSE(std::ifstream(e2e::OutPath("memory_cap_100") + "/report.json").good());
}

// A patch budget: the simplification stops there (it can only stop earlier than the M-fitmap
// halting), the report says so.
TEST(RunPipeline, PatchBudgetIsHonoured) {
  const std::string outdir = e2e::OutPath("pipeline_budget");
  auto r = RunOnSample("--tau 10 --patches 600", "elephant.off", outdir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string json = e2e::Slurp(outdir + "/report.json");
  const double patches = e2e::JsonNumber(json, "patches");
  ASSERT_TRUE(std::isfinite(patches)) << json;
  // The budget stops the simplification early (without it: 413 at tau 10%, when no feasible
  // collapse is left); one step removes a face plus at most a few doublets.
  EXPECT_LE(patches, 600);
  EXPECT_GE(patches, 595);
}

// A budget above what the input's pairing can give: helmet.off has 1 000 triangles, so ~500 quads,
// and a budget of 1 000 patches stopped at 486 (2026-12-02 budget survey). The start is now its
// midpoint refinement (4 000 triangles), and the budget is reached with a valid fit.
TEST(RunPipeline, BudgetAboveTheInputsQuadsIsReachedFromItsRefinement) {
  const PipelineOutputs o = RunForReport("--patches 1000", "helmet.off", "pipeline_budget_helmet");
  ASSERT_EQ(o.run.exitCode, 0) << o.run.output;
  const std::string& json = o.json;
  const std::string& log = o.log;
  EXPECT_NE(log.find("refined 1 times at edge midpoints (4000 triangles"), std::string::npos) << log;
  const double patches = e2e::JsonNumber(json, "patches");
  EXPECT_GE(patches, 980) << json;
  EXPECT_LE(patches, 1000) << json;
  EXPECT_EQ(log.find("was not reached"), std::string::npos) << "no budget warning";
  EXPECT_LE(e2e::JsonNumber(json, "unprojectable_pct"), 0.1) << json;
  // closer than the 486-patch cage of the unrefined start (1.043 per mille; measured 0.846)
  EXPECT_LT(e2e::JsonNumber(json, "rms_limit_permille"), 1.04) << json;
}

// The budget ladder (docs/quad.md "Budget ladder") on cow.off at 400 patches (measured
// 2026-12-03): the first pass stops at 421 (2.19 per mille); the guard's tolerance doubled reaches
// 392 patches that lost the legs (fitted 14 per mille from the cow; kept before 2026-12-02 it gave
// 22 per mille and 3.7 % unprojectable): refused; the start decimated to 1 600 triangles reaches
// 400 (with the doubled guard; the plain guard's pass flips patches): kept, 1.92 per mille,
// 0.15 % unprojectable. Since the flips are judged on the fitted limit (2026-12-05 19:30) the
// plain guard's pass is kept: 400 patches, 1.40 per mille, 0.075 %.
TEST(RunPipeline, BudgetLadderRefusesACageThatLostAPartAndReachesTheBudgetFromACoarseStart) {
  const PipelineOutputs o = RunForReport("--patches 400", "cow.off", "pipeline_budget_cow");
  ASSERT_EQ(o.run.exitCode, 0) << o.run.output;
  const std::string& json = o.json;
  const std::string& log = o.log;
  EXPECT_NE(log.find("doubled reached"), std::string::npos) << "the first rung ran";
  EXPECT_NE(log.find("but was not kept: fitted"), std::string::npos) << log;
  ExpectBudgetReachedFromDecimatedStart(o, 400, 1600);
  EXPECT_EQ(o.run.output.find("warning: Fitmap Quad Simplification: the budget"), std::string::npos) << o.run.output;
  // the kept cage fits the scan: RMS limit under 3 per mille (the refused cage: 22), unprojectable
  // under 0.25 % (0.15; the refused cage 3.7 %, issue 13's target 0.1 % is not met here)
  EXPECT_LE(e2e::JsonNumber(json, "rms_limit_permille"), 3.0) << json;
  EXPECT_LE(e2e::JsonNumber(json, "unprojectable_pct"), 0.25) << json;
  EXPECT_GT(e2e::JsonNumber(json, "budget_retries"), 0) << "the retries are timed: " << json;
}

// The ladder judges a retry by the report's own limit error (docs/quad.md "Budget ladder"),
// measured 2026-12-05: bull.off @ 200 stops at 466 patches (1.46 per mille); with the thin-part
// guard's tolerance doubled a pass reaches 211 that has lost parts of the bull (30 per mille RMS,
// 5.1 % unprojectable), which the fit's own data rows had judged close enough and kept. Now it is
// refused: the budget is missed, the log says so, and the cage covers the bull (the bounds: 3 x
// the measured error, and issue 13's 0.1 % unprojectable; the refused cage is 20x and 50x that).
TEST(RunPipeline, BudgetLadderRefusesARetryTheReportWouldFindFarOff) {
  const PipelineOutputs o = RunForReport("--patches 200", "bull.off", "pipeline_budget_bull");
  ASSERT_EQ(o.run.exitCode, 0) << o.run.output;
  EXPECT_NE(o.log.find("but was not kept: fitted, its limit is"), std::string::npos) << o.log;
  EXPECT_NE(o.log.find("was not reached"), std::string::npos) << "the budget warning";
  // and run_pipeline.sh repeats it last (report.json has only the fit's warnings)
  const size_t w = o.run.output.find("[run_pipeline] warning: Fitmap Quad Simplification: the budget of 200");
  EXPECT_NE(w, std::string::npos) << o.run.output;
  EXPECT_GT(w, o.run.output.find("[run_pipeline] report")) << "after the report";
  EXPECT_GT(e2e::JsonNumber(o.json, "patches"), 300) << o.json;
  EXPECT_LE(e2e::JsonNumber(o.json, "rms_limit_permille"), 4.5) << o.json;
  EXPECT_LE(e2e::JsonNumber(o.json, "unprojectable_pct"), 0.1) << o.json;
}

// The ladder judges a retry whose interpolating limit flips more patches than the first pass's by
// the folds of its fitted limit (docs/quad.md "Budget ladder"), measured 2026-12-05: elephant.off
// @ 200, the first pass stops at 339 patches, the guard relaxed at 231; the 500-triangle start
// reaches 200 with one flip more, but fitted, its limit folds 35 triangles (the 231's: 69) at
// 2.56 per mille RMS (2.22 at 231 patches), 0.016 % unprojectable. Before, any more flips refused
// it and the budget was missed at 231. The bounds: the budget within 2 %; the error allowed by
// the ladder (twice the first pass's, scaled by the patch ratio) is ~4.4 per mille, 3.0 is 1.2x
// the measure; no more folds than the 231 patches' 69.
TEST(RunPipeline, BudgetLadderJudgesFlipsOnTheFittedLimit) {
  const PipelineOutputs o = RunForReport("--patches 200", "elephant.off", "pipeline_budget_elephant");
  ASSERT_EQ(o.run.exitCode, 0) << o.run.output;
  ExpectBudgetReachedFromDecimatedStart(o, 200, 500);
  EXPECT_LE(e2e::JsonNumber(o.json, "rms_limit_permille"), 3.0) << o.json;
  EXPECT_LE(e2e::JsonNumber(o.json, "folded_triangles_limit"), 69) << o.json;
  EXPECT_LE(e2e::JsonNumber(o.json, "unprojectable_pct"), 0.1) << o.json;
}

// The ladder's last rung and a budget from a start too coarse (docs/quad.md "Budget ladder", "A
// start too coarse"), measured 2026-12-03. turbine.off @ 400: the first pass stops at 2 040, the
// 1 600-triangle start at 507 (flips and the guard refuse the rest); the 1 000-triangle start (2.5 N)
// reaches 400 patches, 1.11 per mille, 0.07 % unprojectable. rotor.off @ 400 (1 200 triangles: no
// coarser start) kept 515 patches 38 per mille off the part (25 displaced, 1.6 % unprojectable);
// from its start refined at edge midpoints 683 patches at 2.6 (0.35 displaced, 0 %): the budget is
// still missed, and the log says so, but the cage fits.
TEST(RunPipeline, BudgetLadderLastRungAndBudgetFromARefinedStart) {
  const PipelineOutputs t = RunForReport("--patches 400", "turbine.off", "pipeline_budget_turbine");
  ASSERT_EQ(t.run.exitCode, 0) << t.run.output;
  ExpectBudgetReachedFromDecimatedStart(t, 400, 1000);
  // 0.07 % with the fit before 2026-12-04; 0.102 % (RMS limit 1.05) since the fit returns its
  // lowest-data-RMS iterate (docs/fit.md "Which iterate is kept"): issue 13's 0.1 % is missed here
  // by 0.002 % (open, README). The bound still fails a cage that lost a part (1.6 % unprojectable,
  // rotor's kept wreck below) and is 1.5x the target.
  EXPECT_LE(e2e::JsonNumber(t.json, "unprojectable_pct"), 0.15) << t.json;
  EXPECT_LE(e2e::JsonNumber(t.json, "rms_limit_permille"), 1.5) << t.json;  // 507 patches: 1.04
  const PipelineOutputs r = RunForReport("--patches 400", "rotor.off", "pipeline_budget_rotor");
  ASSERT_EQ(r.run.exitCode, 0) << r.run.output;
  EXPECT_NE(r.log.find("simplified again from the start refined 1 time(s)"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("was not reached"), std::string::npos) << "the budget warning";
  EXPECT_LT(e2e::JsonNumber(r.json, "rms_limit_permille"), 5.0) << r.json;
  EXPECT_LT(e2e::JsonNumber(r.json, "rms_displaced_permille"), 1.0) << r.json;
  EXPECT_LE(e2e::JsonNumber(r.json, "unprojectable_pct"), 0.1) << r.json;
}

// A start too coarse for its input (docs/quad.md "A start too coarse"), measured 2026-12-03:
// rotor.off (1 200 long CAD triangles) used to keep 515 of its 599 pairs with the limit 40.6 per
// mille (RMS) from the part after the fit, 21.6 displaced, 2.1 % unprojectable; from its start
// refined at edge midpoints 737 patches at 2.49 (0.34 displaced, 0 %). spool.off: 429 patches
// that stayed off, from the refined start 552 at 3.25 (0.48 displaced, 0.035 %). The log says so
// and the stage is timed. (oblong-shuffled.off was the second mesh here until its isotropic start
// was made deterministic: RemeshedStartLiesOnTheInput, and FarOffCageIsNotKeptSilently.)
//
// spool's coarse cage is a borderline case (found 2026-12-05 on an AMD EPYC host, AVX2, not the
// host of the measurements above; Embree picks its kernels by CPU and they round differently): its 429
// patches fit to 1.89 per mille (0.73 displaced, 0.087 %), closer than the refined start's 552,
// so the refined cage is tried and not kept, and the log says so. Which cage is kept is not the
// contract; the bounds below and a log that names the retry are. rotor's coarse cage (29 per
// mille off after the fit on both hosts) must be replaced.
TEST(RunPipeline, StartTooCoarseForTheInputIsRefined) {
  for (const char* mesh : {"rotor.off", "spool.off"}) {
    SCOPED_TRACE(mesh);
    const PipelineOutputs o = RunForReport("", mesh, std::string("pipeline_start_") + mesh);
    ASSERT_EQ(o.run.exitCode, 0) << o.run.output;
    const bool refined = o.log.find("simplified again from the start refined 1 time(s)") != std::string::npos;
    const bool triedNotKept = o.log.find("did not cover the input better") != std::string::npos;
    EXPECT_TRUE(refined || triedNotKept) << "the retry is named: " << o.log;
    if (std::string(mesh) == "rotor.off") {
      EXPECT_TRUE(refined) << o.log;
    }
    EXPECT_LT(e2e::JsonNumber(o.json, "rms_limit_permille"), 5.0) << o.json;
    EXPECT_LT(e2e::JsonNumber(o.json, "rms_displaced_permille"), 1.0) << o.json;
    EXPECT_LE(e2e::JsonNumber(o.json, "unprojectable_pct"), 0.1) << o.json;
    EXPECT_GT(e2e::JsonNumber(o.json, "start_refinement"), 0) << o.json;
  }
}

// A cage far off after the guards (docs/quad.md "A cage far off"), measured 2026-12-03:
// oblong-shuffled.off (a box with a blind hole, a cone apex of valence 36: the start is an
// isotropic remesh) is the part whose result moved with the remesh's stack garbage (895 patches
// at 1.8 per mille RMS limit, or 142 at 55) and, remeshed with the projection radius at the whole
// diagonal, kept 436 patches 53 per mille off (the fit's own data RMS said 2.0) until
// RescueByBudget laid it out again under a budget (5.7). With the radius at MeshLab's 1 %: 434
// patches at 7.7 per mille, 1.0 displaced, 0.01 % unprojectable, the rescue not needed (with the
// fit's sample rows at weight 0.25, 2026-12-04: 6.2 per mille, 1.54 displaced, 0.07 %; the
// displaced bound 1.5 -> 2.0, still a quarter of the warning's 5). The
// contract, whatever the start: the limit within tau of the part (10 per mille, RMS) and a
// limit or a displacement that far off named in the log (ResultWarnings' thresholds: 20 per
// mille max limit, 5 per mille RMS displaced). RescueByBudget itself:
// Coverage.RescueByBudgetReplacesACageThatMissesAPart.
TEST(RunPipeline, FarOffCageIsNotKeptSilently) {
  const PipelineOutputs o = RunForReport("", "oblong-shuffled.off", "pipeline_far_oblong");
  ASSERT_EQ(o.run.exitCode, 0) << o.run.output;
  EXPECT_NE(o.log.find("isotropic remesh"), std::string::npos) << o.log;
  EXPECT_LT(e2e::JsonNumber(o.json, "rms_limit_permille"), 10.0) << o.json;  // tau
  EXPECT_LT(e2e::JsonNumber(o.json, "rms_displaced_permille"), 2.0) << o.json;
  EXPECT_LE(e2e::JsonNumber(o.json, "unprojectable_pct"), 0.1) << o.json;
  ASSERT_GT(e2e::JsonNumber(o.json, "max_limit_permille"), 0) << o.json;
  if (e2e::JsonNumber(o.json, "max_limit_permille") > 20) {
    EXPECT_NE(o.log.find("the smooth limit surface stays up to"), std::string::npos) << o.log;
  }
  if (e2e::JsonNumber(o.json, "rms_displaced_permille") > 5) {
    EXPECT_NE(o.log.find("the displaced surface stays"), std::string::npos) << o.log;
  }
}

// --regularity W (the filter's "regularity", QuadSimplifyParams::valenceWeight) reaches the
// simplification: at the same budget the cage has fewer irregular vertices (elephant @ 400,
// measured 2026-12-02: 162 with 0, 123 with 1) and stays a valid fit (a negative weight:
// RejectsBadArguments).
TEST(RunPipeline, RegularityWeightGivesFewerIrregularVerticesAtABudget) {
  int irregular[2] = {0, 0};
  for (int w = 0; w < 2; ++w) {
    const std::string outdir = e2e::OutPath("pipeline_regularity_" + std::to_string(w));
    auto r = RunOnSample("--patches 400 --regularity " + std::to_string(w), "elephant.off", outdir);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string json = e2e::Slurp(outdir + "/report.json");
    EXPECT_NEAR(e2e::JsonNumber(json, "patches"), 400, 8) << json;
    EXPECT_LE(e2e::JsonNumber(json, "unprojectable_pct"), 0.1) << json;
    irregular[w] = int(e2e::JsonNumber(json, "irregular_vertices"));
  }
  EXPECT_LT(irregular[1], 0.9 * irregular[0]) << irregular[0] << " -> " << irregular[1];
}

// --trials K (the filter's "layoutTrials", QuadSimplifyParams::layoutTrials; docs/quad.md "Layout
// trials") under a budget: the trials are judged by the fit the pipeline runs (FitCatmullClark
// with default parameters, TrialFittedRms), the log lists every trial's judged RMS and the kept
// one is the lowest (the first trial, weight 0, is the single layout); the pipeline's own fit of
// the kept cage agrees with its judged RMS (the report's limit error is measured on a finer
// tessellation: 3 % of slack; measured 0.7766 against 0.777). The log names the trials, the
// report times them. Measured 2026-12-03 on elephant @ 400: 162 irregular / 0.941 per mille with
// one layout, 139 / 0.808 with four (weight 0.25 kept).
// Not asserted (found 2026-12-05 on an AMD EPYC host): that the kept cage's report beats the
// single layout's report. There the single run's cage fitted to 0.733 per mille in the pipeline
// while the same layout was judged 0.851 inside the trials run (docs/quad.md "Layout trials").
TEST(RunPipeline, LayoutTrialsKeepTheCageThatFitsClosest) {
  double rms[2] = {0, 0};
  std::string trialsLog;
  for (int k = 0; k < 2; ++k) {
    const std::string outdir = e2e::OutPath("pipeline_trials_" + std::to_string(k));
    auto r = RunOnSample(std::string("--patches 400 --trials ") + (k ? "4" : "1"), "elephant.off", outdir);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string json = e2e::Slurp(outdir + "/report.json");
    const std::string log = e2e::Slurp(outdir + "/meshlab.log");
    EXPECT_NEAR(e2e::JsonNumber(json, "patches"), 400, 8) << json;
    EXPECT_LE(e2e::JsonNumber(json, "unprojectable_pct"), 0.1) << json;
    rms[k] = e2e::JsonNumber(json, "rms_limit_permille");
    EXPECT_EQ(log.find("layout trials") != std::string::npos, k == 1) << log;
    EXPECT_EQ(json.find("\"layout_trials\"") != std::string::npos, k == 1) << json;
    if (k == 1) trialsLog = log;
  }
  std::printf("elephant @ 400: single layout %.4f, trials %.4f per mille (reports)\n", rms[0], rms[1]);
  // "kept the one with weight W (...; weight: patches, RMS per mille: 0: 400 patches, 0.851; 0.25: ...)"
  const size_t keptAt = trialsLog.find("kept the one with weight ");
  const size_t listAt = trialsLog.find("RMS per mille: ", keptAt);
  ASSERT_NE(keptAt, std::string::npos) << trialsLog;
  ASSERT_NE(listAt, std::string::npos) << trialsLog;
  const double keptWeight = std::stod(trialsLog.substr(keptAt + 25));
  const std::string list = trialsLog.substr(listAt + 15, trialsLog.find(')', listAt) - listAt - 15);
  double keptJudged = -1, lowest = 1e300;
  int trials = 0;
  for (size_t at = 0; at < list.size();) {
    const size_t end = std::min(list.find("; ", at), list.size());
    const std::string item = list.substr(at, end - at);  // "W: P patches, R"
    const double w = std::stod(item), judged = std::stod(item.substr(item.rfind(", ") + 2));
    lowest = std::min(lowest, judged);
    if (w == keptWeight) keptJudged = judged;
    ++trials;
    at = end + 2;
  }
  EXPECT_EQ(trials, 4) << list;
  ASSERT_GT(keptJudged, 0) << list;
  EXPECT_EQ(keptJudged, lowest) << "the kept trial is the closest judged: " << list;
  EXPECT_NEAR(rms[1], keptJudged, 0.03 * keptJudged) << "the pipeline's fit of the kept cage is the judged one: " << list;
}

// Layout trials without a budget do nothing, and say so (the script and the filter's log) instead
// of silently running one layout.
TEST(RunPipeline, LayoutTrialsWithoutABudgetAreNamedAndIgnored) {
  const std::string outdir = e2e::OutPath("pipeline_trials_no_budget");
  auto r = RunOnSample("--trials 3", "elephant.off", outdir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("--trials needs --patches N"), std::string::npos) << r.output;
  const std::string log = e2e::Slurp(outdir + "/meshlab.log");
  EXPECT_NE(log.find("layout trials need a target patch count"), std::string::npos) << log;
  EXPECT_EQ(log.find("layout trials ("), std::string::npos) << log;
}

}  // namespace

// A thin sheet (docs/robustness.md "Thin sheets"): the data set's blade.off (a turbine blade, 95 %
// of its area within 0.4 % of the diagonal of its other side) at tau = 1 % keeps 3 661 patches at
// RMS limit 0.022 per mille, and the simplification says why and advises a budget; with
// `--patches 300` the cage has 300 patches at 0.019 (measured 2026-12-06) and no such warning.
// Asserted: the warning at tau and not under a budget, and the budget's cage at most a fifth of
// tau's patches and within 1.5 x its limit error (a worse fit would make the advice wrong).
TEST(RunPipeline, ThinSheetIsWarnedAtTauAndABudgetFitsAsCloseWithFewerPatches) {
  const PipelineOutputs tau = RunForReport("", "blade.off", "pipeline_thin_blade");
  ASSERT_EQ(tau.run.exitCode, 0) << tau.run.output;
  EXPECT_NE(tau.log.find("of the input's area is a thin sheet"), std::string::npos) << tau.log;
  const PipelineOutputs budget = RunForReport("--patches 300", "blade.off", "pipeline_thin_blade_300");
  ASSERT_EQ(budget.run.exitCode, 0) << budget.run.output;
  EXPECT_EQ(budget.log.find("is a thin sheet"), std::string::npos) << budget.log;
  EXPECT_NEAR(e2e::JsonNumber(budget.json, "patches"), 300, 6) << budget.json;
  EXPECT_LT(5 * e2e::JsonNumber(budget.json, "patches"), e2e::JsonNumber(tau.json, "patches")) << tau.json;
  EXPECT_LT(e2e::JsonNumber(budget.json, "rms_limit_permille"), 1.5 * e2e::JsonNumber(tau.json, "rms_limit_permille"))
      << budget.json << tau.json;
  EXPECT_LE(e2e::JsonNumber(budget.json, "unprojectable_pct"), 0.1) << budget.json;
}
