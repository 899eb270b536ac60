/// \file layout_trials.cpp
/// Under a budget: the layout pass with several valence weights, the cage that fits closest kept
/// (QuadSimplifyParams::layoutTrials; docs/quad.md "Layout trials").
#include <algorithm>
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

QuadSimplifyResult LayoutTrials(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress& prog, const std::vector<Quad>* initialQuads) {
  const int target = params.targetPatches;
  const std::vector<double> weights = TrialValenceWeights(params.valenceWeight, std::max(1, params.layoutTrials));
  const int n = int(weights.size());
  auto pass = [&](int i) {
    QuadSimplifyParams lp = LayoutParams(params, target);
    lp.valenceWeight = weights[size_t(i)];
    Progress sub = prog.Sub(100.0 * i / n, 100.0 * (i + 1) / n);
    return SimplifyOnce(input, start, scene, S, M, lp, n == 1 ? prog : sub, initialQuads);
  };
  QuadSimplifyResult kept = pass(0);
  if (n == 1 || !kept.error.empty()) return kept;
  const auto fitted = [&](const QuadSimplifyResult& x) {
    return BudgetReached(x.patches, target) ? FittedReferenceRms(input, scene, x.quads)
                                            : std::numeric_limits<double>::infinity();
  };
  const int firstFlips = kept.flippedPatches + kept.flippedVertices;
  double keptFit = fitted(kept), spent = 0;
  kept.trialValenceWeight = weights[0];
  for (int i = 1; i < n; ++i) {
    QuadSimplifyResult g = pass(i);
    const bool usable = g.error.empty() && g.flippedPatches + g.flippedVertices <= firstFlips;
    const double gFit = usable ? fitted(g) : std::numeric_limits<double>::infinity();
    if (!usable || !TrialBeats(g, gFit, kept, keptFit, target)) {
      spent += g.secondsTotal;
      continue;
    }
    spent += kept.secondsTotal;
    g.trialValenceWeight = weights[size_t(i)];
    kept = std::move(g);
    keptFit = gFit;
  }
  kept.layoutTrialsRun = n;
  kept.secondsLayoutTrials = spent;
  kept.secondsTotal += spent;
  return kept;
}

}  // namespace simplify_internal
}  // namespace vcgext
