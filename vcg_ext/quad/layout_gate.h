#pragma once
// The gate between the equalized layout's two passes when they run on two threads
// (vcgext::SimplifyToQuads, Layout::Equalized; docs/quad.md "Layout").
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <limits>
#include <mutex>

namespace vcgext {
namespace quad {

/// The layout pass's patch target while the count pass that sets it runs on another thread
/// (Layout::Equalized, docs/quad.md "Layout": the two passes overlap). The layout pass stops at the
/// first count <= its target, so its run is the sequential one as long as none of its steps
/// started at or below the target: Set checks that under the lock and cancels the layout pass
/// otherwise (it is then redone after the count). Until the target is known the layout pass steps
/// while its count is above the floor (a bound the count is expected not to exceed: countFaces / 16
/// for a coarse count, raised towards a bound of a recount by RaiseFloor) or above the live count
/// of a count pass on the same start (Publish: that pass only removes patches, so its live count
/// bounds its result), and waits otherwise.
class LayoutGate {
 public:
  explicit LayoutGate(int floor) : floor_(floor) {}
  /// 0: not known yet; > 0: the target; < 0: cancelled.
  int Target() const { return target_.load(std::memory_order_acquire); }
  /// The count pass's result (<= 0: an error or no count): cancels the layout pass if one of its
  /// steps started at or below it.
  void Set(int target) {
    {
      std::lock_guard<std::mutex> g(m_);
      if (target <= 0 || target >= lowestStep_) target = -1;
      target_.store(target, std::memory_order_release);
    }
    cv_.notify_all();
  }
  /// Called by the layout pass before each step from `count` patches: the target (0: not known
  /// yet; < 0: cancelled); blocks while the step may not start, adding the time waited to `waited`.
  int Admit(int count, double* waited) {
    int t = Target();
    if (t != 0) return t;
    std::unique_lock<std::mutex> l(m_);
    if (!(count > floor_ || count > live_) && target_.load(std::memory_order_acquire) == 0) {
      // woken by Set, RaiseFloor, or a live count a few steps below this one (not every step)
      const auto t0 = std::chrono::steady_clock::now();
      waitingAt_ = count;
      cv_.wait(l, [&] {
        return target_.load(std::memory_order_acquire) != 0 || count > floor_ || live_ < count - Slack(count);
      });
      waitingAt_ = 0;
      *waited += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    t = target_.load(std::memory_order_acquire);
    if (t == 0) lowestStep_ = count;  // a step starts from `count`
    return t;
  }
  /// Raises the floor towards `floor`: up to just below the count the layout pass's latest step
  /// started from (a higher floor would not bound what it has already passed), so a layout pass
  /// already below `floor` stops where it is.
  void RaiseFloor(int floor) {
    {
      std::lock_guard<std::mutex> g(m_);
      floor_ = std::max(floor_, std::min(floor, lowestStep_ - 1));
    }
    cv_.notify_all();
  }
  /// The count the layout pass is waiting at (0: not waiting).
  int WaitingAt() const {
    std::lock_guard<std::mutex> g(m_);
    return waitingAt_;
  }
  /// The live patch count of a count pass on the layout pass's own start mesh.
  void Publish(int count) {
    bool wake = false;
    {
      std::lock_guard<std::mutex> g(m_);
      live_ = count;
      wake = waitingAt_ > 0 && live_ < waitingAt_ - Slack(waitingAt_);
    }
    if (wake) cv_.notify_all();
  }

 private:
  static int Slack(int count) { return std::max(1, count / 64); }
  int floor_;
  int live_ = std::numeric_limits<int>::max();
  int lowestStep_ = std::numeric_limits<int>::max();  // the count the layout pass's latest step started from
  int waitingAt_ = 0;                                   // the count the layout pass waits at (0: not waiting)
  std::atomic<int> target_{0};
  mutable std::mutex m_;
  std::condition_variable cv_;
};

}  // namespace quad
}  // namespace vcgext
