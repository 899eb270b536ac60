/// \file layout_trials.cpp
/// Under a budget: the layout pass (and its ladder) with several valence weights, the cage that
/// fits closest kept (QuadSimplifyParams::layoutTrials; docs/quad.md "Layout trials").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "vcg_ext/quad/simplify_internal.h"

namespace vcgext {

std::vector<double> TrialValenceWeights(double first, int trials) {
  std::vector<double> w{first};
  for (double c : kTrialValenceWeights)
    if (int(w.size()) < trials && c != first) w.push_back(c);
  return w;
}

namespace simplify_internal {
namespace {

// Whether trial g beats the kept one (k): it reaches the budget and k does not; both reach it and
// g's fitted limit is closer to the input (gFit, kFit); neither does and g comes closer to it.
bool TrialBeats(const QuadSimplifyResult& g, double gFit, const QuadSimplifyResult& k, double kFit, int target) {
  const bool gr = BudgetReached(g.patches, target), kr = BudgetReached(k.patches, target);
  if (gr != kr) return gr;
  if (gr) return gFit < kFit;
  return std::abs(g.patches - target) < std::abs(k.patches - target);
}

}  // namespace

double TrialFittedRms(const TriData& input, const EmbreeScene& scene, const QuadData& quads) {
  return MeasureAsReported(input, scene, quads, false).rms;
}

QuadSimplifyResult LayoutTrials(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress& prog, const std::vector<Quad>* initialQuads) {
  const int target = params.targetPatches;
  const std::vector<double> weights = TrialValenceWeights(params.valenceWeight, std::max(1, params.layoutTrials));
  const int n = int(weights.size());
  if (n == 1) return BudgetLadder(input, start, scene, S, M, params, prog, initialQuads);
  const auto t0 = std::chrono::steady_clock::now();
  // trial i: the budget's layout pass and, where it stops above the budget, its ladder
  auto trial = [&](int i) {
    QuadSimplifyParams tp = params;
    tp.valenceWeight = weights[size_t(i)];
    Progress sub = prog.Sub(100.0 * i / n, 100.0 * (i + 1) / n);
    QuadSimplifyResult g = BudgetLadder(input, start, scene, S, M, tp, sub, initialQuads);
    g.trialValenceWeight = tp.valenceWeight;
    return g;
  };
  const auto fitted = [&](const QuadSimplifyResult& x) {
    return BudgetReached(x.patches, target) ? TrialFittedRms(input, scene, x.quads)
                                            : std::numeric_limits<double>::infinity();
  };
  const double diag = BBoxDiagonal(input.V);
  std::string summary;
  // one trial in the summary: "weight: patches, fitted RMS per mille" ("-": not measured)
  auto note = [&](const QuadSimplifyResult& x, double fit) {
    char buf[96];
    const int len = std::snprintf(buf, sizeof buf, "%s%g: ", summary.empty() ? "" : "; ", x.trialValenceWeight);
    if (!x.error.empty())
      std::snprintf(buf + len, sizeof buf - len, "failed");
    else if (std::isfinite(fit))
      std::snprintf(buf + len, sizeof buf - len, "%d patches, %.3f", x.patches, 1000 * fit / diag);
    else
      std::snprintf(buf + len, sizeof buf - len, "%d patches, -", x.patches);
    summary += buf;
  };
  QuadSimplifyResult kept = trial(0);
  if (!kept.error.empty()) return kept;
  const int firstFlips = kept.flippedPatches + kept.flippedVertices;
  double keptFit = fitted(kept);
  note(kept, keptFit);
  for (int i = 1; i < n; ++i) {
    QuadSimplifyResult g = trial(i);
    const bool usable = g.error.empty() && g.flippedPatches + g.flippedVertices <= firstFlips;
    const double gFit = usable ? fitted(g) : std::numeric_limits<double>::infinity();
    note(g, gFit);
    if (!usable || !TrialBeats(g, gFit, kept, keptFit, target)) continue;
    kept = std::move(g);
    keptFit = gFit;
  }
  kept.layoutTrialsRun = n;
  kept.layoutTrialsSummary = summary;
  const double all = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  kept.secondsLayoutTrials = std::max(0.0, all - kept.secondsTotal);
  kept.secondsTotal = all;
  return kept;
}

}  // namespace simplify_internal
}  // namespace vcgext
