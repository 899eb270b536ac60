// AdaptiveParallelism (vcg_ext/quad/adaptive_parallelism.cpp): serial or parallel checks per step.
#include <gtest/gtest.h>

#include <cmath>

#include <omp.h>

#include "quad_test_util.h"
#include "simplify_test_util.h"

using quadtest::ExpectGuarantees;
using quadtest::RmsLimitDistance;
using quadtest::SyntheticFitmaps;
#include "test_support.h"
#include "vcg_ext/quad/cc_limit.h"
#include "vcg_ext/quad/quad_mesh.h"
#include "vcg_ext/quad/quad_simplify.h"
#include "vcg_ext/core/decimate.h"
#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/fit/cc_fit.h"
#include "vcg_ext/subdiv/limit_surface.h"

using vcgext::Vec3;


// AdaptiveParallelism (the choice of threads for a step's checks) on synthetic timings: it must
// settle on the faster mode, probe the other one ever more rarely, follow a change of load
// within a block or two, and never go parallel when not allowed.
TEST(AdaptiveParallelism, FollowsTheFasterModeAndTheLoad) {
  // Simulates `blocks` blocks; t(parallel) is the time per unit of the block's mode. Returns the
  // share of the steps run in parallel mode.
  auto simulate = [](vcgext::AdaptiveParallelism& a, int blocks, double serial, double parallel) {
    long par = 0, all = 0;
    for (int b = 0; b < blocks; ++b) {
      const int n = a.BlockSteps();
      all += n;
      par += a.Parallel() ? n : 0;
      a.EndBlock(a.Parallel() ? parallel : serial);
    }
    return double(par) / all;
  };
  vcgext::AdaptiveParallelism off(false);
  EXPECT_EQ(simulate(off, 200, 1.0, 0.5), 0.0);
  EXPECT_FALSE(off.Parallel());

  vcgext::AdaptiveParallelism idle(true);  // parallel 30 % faster: mostly parallel
  EXPECT_FALSE(idle.Parallel());            // starts serial
  EXPECT_GT(simulate(idle, 1000, 1.0, 0.7), 0.9);
  EXPECT_LT(idle.Switches(), 40);           // the serial probes back off

  vcgext::AdaptiveParallelism loaded(true);  // parallel 5x slower: almost never
  EXPECT_LT(simulate(loaded, 1000, 1.0, 5.0), 0.01);
  EXPECT_FALSE(loaded.Parallel());

  // Under load a short parallel probe can look fast while longer parallel blocks are slow: the
  // confirmation block must keep the parallel share small.
  vcgext::AdaptiveParallelism optimistic(true);
  long par = 0, all = 0;
  for (int b = 0; b < 1000; ++b) {
    const int n = optimistic.BlockSteps();
    const bool probe = optimistic.Parallel() && n < 64;
    all += n;
    par += optimistic.Parallel() ? n : 0;
    optimistic.EndBlock(!optimistic.Parallel() ? 1.0 : probe ? 0.6 : 2.0);
  }
  EXPECT_LT(double(par) / all, 0.02);

  // Load appears after an idle stretch: serial again within two blocks.
  vcgext::AdaptiveParallelism change(true);
  simulate(change, 300, 1.0, 0.7);
  for (int b = 0; b < 20 && !change.Parallel(); ++b) change.EndBlock(1.0);  // (a serial probe may be running)
  ASSERT_TRUE(change.Parallel());
  change.EndBlock(5.0);
  if (change.Parallel()) change.EndBlock(5.0);
  EXPECT_FALSE(change.Parallel());
  // ... and it goes parallel again once the load is gone.
  EXPECT_GT(simulate(change, 2000, 1.0, 0.7), 0.5);
  EXPECT_TRUE(change.Parallel());

  // A brief load after a long parallel stretch (the serial probes have backed off to their
  // longest interval) must not keep it serial for long once the load is gone.
  vcgext::AdaptiveParallelism burst(true);
  simulate(burst, 2000, 1.0, 0.7);
  for (int b = 0; b < 20 && !burst.Parallel(); ++b) burst.EndBlock(1.0);
  ASSERT_TRUE(burst.Parallel());
  burst.EndBlock(5.0);  // one slow parallel block: back to serial
  ASSERT_FALSE(burst.Parallel());
  int serialBlocks = 0;
  while (!burst.Parallel() && serialBlocks < 1000) {
    burst.EndBlock(burst.Parallel() ? 0.7 : 1.0);
    ++serialBlocks;
  }
  EXPECT_LE(serialBlocks, 10);
}
