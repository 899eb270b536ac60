// vcgext::quad::LayoutGate: the equalized layout's two passes on two threads. The layout pass's
// cage is the sequential one only if no step of it started at or below the count the count pass
// returns; these tests drive the gate from two threads with the steps spelled out.
#include "vcg_ext/quad/layout_gate.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <limits>

namespace {

using vcgext::quad::LayoutGate;
using namespace std::chrono_literals;

// Admit on another thread, which is waiting at `count` (or has returned) when the constructor
// returns; Blocked() tells whether it is still waiting 100 ms later.
struct AdmitOnThread {
  std::future<int> result;
  double waited = 0;
  AdmitOnThread(LayoutGate& g, int count) {
    result = std::async(std::launch::async, [&g, count, this] { return g.Admit(count, &waited); });
    const auto t0 = std::chrono::steady_clock::now();
    while (g.WaitingAt() != count && result.wait_for(1ms) == std::future_status::timeout &&
           std::chrono::steady_clock::now() - t0 < 10s) {
    }
  }
  bool Blocked() { return result.wait_for(100ms) == std::future_status::timeout; }
};

TEST(LayoutGate, ACountBelowEveryStepIsTheTargetAndOneAtOrAboveAStepCancels) {
  {
    LayoutGate g(10);
    double waited = 0;
    EXPECT_EQ(g.Admit(20, &waited), 0);  // above the floor: the step from 20 may start
    g.Set(19);
    EXPECT_EQ(g.Target(), 19);
    EXPECT_EQ(waited, 0.0);
  }
  {
    LayoutGate g(10);
    double waited = 0;
    EXPECT_EQ(g.Admit(20, &waited), 0);
    g.Set(20);  // the sequential pass would have stopped at 20, before that step
    EXPECT_LT(g.Target(), 0);
  }
  {
    LayoutGate g(10);
    g.Set(0);  // the count pass failed
    EXPECT_LT(g.Target(), 0);
  }
}

TEST(LayoutGate, TheLayoutPassWaitsAtTheFloorUntilTheCountIsKnown) {
  LayoutGate g(10);
  double waited = 0;
  EXPECT_EQ(g.Admit(11, &waited), 0);
  AdmitOnThread a(g, 10);
  EXPECT_TRUE(a.Blocked());
  g.Set(7);
  EXPECT_EQ(a.result.get(), 7);
  EXPECT_GT(a.waited, 0.05);
  EXPECT_EQ(g.Target(), 7);
}

TEST(LayoutGate, ARaisedFloorStopsAtTheLayoutPassesLatestStep) {
  LayoutGate g(5);
  double waited = 0;
  EXPECT_EQ(g.Admit(30, &waited), 0);  // a step from 30 has started
  g.RaiseFloor(100);                   // a floor above 30 would bound nothing: 29
  AdmitOnThread a(g, 29);
  EXPECT_TRUE(a.Blocked());
  g.Set(29);  // below the step from 30: valid
  EXPECT_EQ(a.result.get(), 29);
  EXPECT_EQ(g.Target(), 29);
}

TEST(LayoutGate, ARaisedFloorBelowTheLayoutPassLetsItGoOnDownToIt) {
  LayoutGate g(5);
  double waited = 0;
  EXPECT_EQ(g.Admit(300, &waited), 0);
  g.RaiseFloor(40);
  EXPECT_EQ(g.Admit(41, &waited), 0);  // still above the raised floor
  AdmitOnThread a(g, 40);
  EXPECT_TRUE(a.Blocked());
  g.Set(35);
  EXPECT_EQ(a.result.get(), 35);
}

TEST(LayoutGate, TheLayoutPassFollowsTheLiveCountOfACountPassOnItsStart) {
  LayoutGate g(std::numeric_limits<int>::max());  // no floor: only the live count lets it go on
  AdmitOnThread a(g, 100);
  EXPECT_TRUE(a.Blocked());  // nothing known yet
  g.Publish(99);             // one below: not yet worth a wake-up (slack max(1, 100 / 64))
  EXPECT_TRUE(a.Blocked());
  g.Publish(98);
  EXPECT_EQ(a.result.get(), 0);  // the step from 100 may start
  double waited = 0;
  EXPECT_EQ(g.Admit(99, &waited), 0);  // above the live count: no wait
  AdmitOnThread b(g, 98);              // at the live count: waits
  EXPECT_TRUE(b.Blocked());
  g.Set(98);  // below the step from 99: valid, and it ends the wait
  EXPECT_EQ(b.result.get(), 98);
}

}  // namespace
