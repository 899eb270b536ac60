// Layout trials under a budget (vcg_ext/quad/layout_trials.cpp, docs/quad.md "Layout trials").
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "quad_test_util.h"
#include "simplify_test_util.h"
#include "test_support.h"
#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/quad/quad_simplify.h"
#include "vcg_ext/quad/simplify_internal.h"

using quadtest::ExpectGuarantees;
using quadtest::SyntheticFitmaps;
using vcgext::Vec3;

// The weights: the user's first, then 0, 0.25, 1, 0.05 without it, as many as asked (0.25 second:
// at one weight it halves the irregular vertices at 1 000 patches, docs/quad.md "Regularity").
TEST(LayoutTrials, WeightsStartWithTheUsersOwn) {
  EXPECT_EQ(vcgext::TrialValenceWeights(0, 1), (std::vector<double>{0}));
  EXPECT_EQ(vcgext::TrialValenceWeights(0, 4), (std::vector<double>{0, 0.25, 1, 0.05}));
  EXPECT_EQ(vcgext::TrialValenceWeights(0, 5), (std::vector<double>{0, 0.25, 1, 0.05})) << "four distinct at most";
  EXPECT_EQ(vcgext::TrialValenceWeights(0.25, 3), (std::vector<double>{0.25, 0, 1}));
  EXPECT_EQ(vcgext::TrialValenceWeights(0, 2), (std::vector<double>{0, 0.25}));
  EXPECT_EQ(vcgext::TrialValenceWeights(0.3, 5), (std::vector<double>{0.3, 0, 0.25, 1, 0.05}));
}

// The rule that decides where the ladder and the trials run, and where the filter warns that the
// trials are ignored: the equalized layout with a budget, nothing else.
TEST(LayoutTrials, RunOnlyUnderABudgetsLayout) {
  vcgext::QuadSimplifyParams p;
  EXPECT_FALSE(vcgext::BudgetLayout(p)) << "no budget";
  p.targetPatches = 400;
  EXPECT_TRUE(vcgext::BudgetLayout(p));
  p.layout = vcgext::QuadSimplifyParams::Layout::PaperHalting;
  EXPECT_FALSE(vcgext::BudgetLayout(p)) << "the paper's halting ignores the budget's layout";
}

// An ellipsoid (5 120 triangles, S from curvature) with a budget of 100 patches and 4 trials: the
// kept cage is, bit for bit, the single layout with the kept weight; brute force over the four
// single layouts, none that reaches the budget fits closer (TrialFittedRms, the selection's
// measure: the RMS distance from the input's vertices to the fitted limit); the guarantees hold
// (the layout pass's validity after every operation is QuadSimplify's tests'); one trial is the
// plain layout pass.
TEST(LayoutTrials, KeepTheLayoutThatFitsClosest) {
  auto t = testsupport::Icosphere(4);
  for (auto& v : t.V) v = Vec3(v[0], 0.6 * v[1], 0.4 * v[2]);
  vcgext::EmbreeScene scene(t);
  std::vector<double> S, M;
  SyntheticFitmaps(t, S, M);
  vcgext::QuadSimplifyParams p;
  p.targetPatches = 100;
  p.layoutTrials = 4;
  const auto r = vcgext::SimplifyToQuads(t, scene, S, M, p);
  ASSERT_EQ(r.error, "");
  ExpectGuarantees(t, r);
  EXPECT_TRUE(vcgext::BudgetReached(r.patches, 100)) << r.patches;
  EXPECT_EQ(r.layoutTrialsRun, 4);
  EXPECT_GT(r.secondsLayoutTrials, 0);
  const double kept = vcgext::simplify_internal::TrialFittedRms(t, scene, r.quads);
  std::printf("ellipsoid, 100 patches, 4 trials: kept weight %g, %d patches, %d irregular, fitted RMS %.5f\n",
              r.trialValenceWeight, r.patches, r.irregularVertices, kept);
  bool keptFound = false;
  for (double w : vcgext::TrialValenceWeights(0, 4)) {
    vcgext::QuadSimplifyParams one = p;
    one.layoutTrials = 1;
    one.valenceWeight = w;
    const auto g = vcgext::SimplifyToQuads(t, scene, S, M, one);
    ASSERT_EQ(g.error, "");
    EXPECT_EQ(g.layoutTrialsRun, 0) << "one trial: the plain layout pass";
    const double fitted = vcgext::simplify_internal::TrialFittedRms(t, scene, g.quads);
    std::printf("  weight %g: %d patches, %d irregular, fitted RMS %.5f\n", w, g.patches, g.irregularVertices, fitted);
    if (vcgext::BudgetReached(g.patches, 100)) {
      EXPECT_GE(fitted, kept) << "weight " << w;
    }
    if (w == r.trialValenceWeight) {
      keptFound = true;
      EXPECT_EQ(g.quads.F, r.quads.F);
      EXPECT_EQ(g.quads.V, r.quads.V);
    }
  }
  EXPECT_TRUE(keptFound) << r.trialValenceWeight;
}

// A budget the first pass misses: each trial goes down its own ladder (docs/quad.md "Budget
// ladder"), so the trials are compared at the budget. The cigar of BudgetStoppedByTheThinPart-
// GuardGoesDownTheLadder (its first pass: 24 patches for 12) with two trials reaches 12 patches by a
// ladder's rung, and fits no farther than the one-trial run, which is its first trial.
TEST(LayoutTrials, EachTrialGoesDownItsOwnLadder) {
  quadtest::CigarBudget c;
  const auto& t = c.t;
  vcgext::EmbreeScene scene(t);
  const auto one = vcgext::SimplifyToQuads(t, scene, c.S, c.M, c.p);
  c.p.layoutTrials = 2;
  const auto two = vcgext::SimplifyToQuads(t, scene, c.S, c.M, c.p);
  ASSERT_EQ(one.error, "");
  ASSERT_EQ(two.error, "");
  ExpectGuarantees(t, two);
  EXPECT_EQ(two.layoutTrialsRun, 2);
  EXPECT_TRUE(vcgext::BudgetReached(two.patches, 12)) << two.patches;
  EXPECT_GT(two.budgetRelaxations, 0) << "a rung's cage";
  EXPECT_GT(two.budgetFromPatches, 12);
  const double f1 = vcgext::simplify_internal::TrialFittedRms(t, scene, one.quads);
  const double f2 = vcgext::simplify_internal::TrialFittedRms(t, scene, two.quads);
  std::printf("cigar, budget 12: one trial %d patches (rung %d) fitted %.5f; two trials %d patches (rung %d, weight %g) fitted %.5f\n",
              one.patches, one.budgetRelaxations, f1, two.patches, two.budgetRelaxations, two.trialValenceWeight, f2);
  EXPECT_LE(f2, f1);
}
