// Issue 16 end to end: every input of the bad-input corpus (tests/corpus/make_corpus.py: 59
// generated files with their expected verdicts) and every mesh of the libcgal-demo data set,
// through Compute Fitmaps, the whole pipeline and both Loop filters with meshlabserver
// (tests/corpus/run_corpus.py). Zero crashes, hangs (600 s per run: the slowest data-set run,
// cheese.off's pipeline, takes 31 s on an idle 2-core machine and ran past 120 s in CI beside
// ctest -j2's other tests; far1e7.off, a float-rounded blob, is now a clear error: its pipeline
// refined it into 4 728 patches in 314 s on a slow AMD host on 2026-12-05), silent wrong results,
// unexpected or unclear errors; files that crash MeshLab 2020.09's own readers are listed apart.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "e2e_support.h"

namespace {
std::string Corpus(const std::string& extra, const std::string& out) {
  const std::string src = FITMAP_SOURCE_DIR;
  const std::string dir = e2e::OutPath("corpus_inputs");
  e2e::RunResult g = e2e::Run("python3 " + e2e::Q(src + "/tests/corpus/make_corpus.py") + " " + e2e::Q(dir));
  EXPECT_EQ(g.exitCode, 0) << g.output;
  e2e::RunResult r = e2e::Run("python3 " + e2e::Q(src + "/tests/corpus/run_corpus.py") + " --jobs 2 --timeout 600 " +
                              extra + " " + e2e::Q(dir) + " " + e2e::Q(e2e::OutPath(out)));
  // the verdict table and the failing runs, for the CI log
  const size_t table = r.output.find("verdict ");
  std::printf("%s\n", r.output.substr(table == std::string::npos ? 0 : table).c_str());
  EXPECT_EQ(r.exitCode, 0) << "failing runs (see the table above)";
  return r.output;
}
}  // namespace

TEST(Corpus, EveryBadInputThroughEveryFilter) {
  std::string out = Corpus("", "corpus_run");
  EXPECT_NE(out.find("valid"), std::string::npos);
  EXPECT_NE(out.find("clear-error"), std::string::npos);
}

// Every filter on every data-set mesh is 690 runs: 6 060 s of runs, 50 min of a slow 2-core CI
// machine (2026-12-05), more than CI can give it beside the other tests. CI runs a fixed sample
// (run_corpus.py --sample 2): every mesh through Compute Fitmaps (the first stage of every filter:
// reading, cleaning and the checks on the input) and every second mesh, in name order, through one
// of the pipeline, the budgeted pipeline, Loop refinement and Loop curvature in turn (about 17
// meshes each, ~950 s of runs). FITMAP_FULL_CORPUS=1 runs all 690, as before a release;
// docs/robustness.md keeps the latest full run's table.
TEST(Corpus, EveryDataSetMeshThroughEveryFilter) {
  const char* full = std::getenv("FITMAP_FULL_CORPUS");
  const bool all = full && std::string(full) == "1";
  std::string out = Corpus("--include-dataset " + e2e::Q(FITMAP_DATA_DIR) + " --only 'data/*'" +
                               (all ? std::string() : std::string(" --sample 2")),
                           "dataset_run");
  EXPECT_NE(out.find("valid"), std::string::npos);
  if (!all) {
    EXPECT_NE(out.find("--sample 2: "), std::string::npos) << "the sample's line is missing";
  }
}
