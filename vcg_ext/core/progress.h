#pragma once
/// \file progress.h
/// Throttled progress reporting through vcglib's `CallBackPos` (MeshLab's GUI callback pumps
/// the Qt event loop: call it only from the calling thread, outside parallel loops, and at most
/// ~10 times a second). Library code never prints.
#include <wrap/callback.h>

#include <chrono>

namespace vcgext {

class Progress {
 public:
  /// Maps stage-local percentages [0,100] into [lo, hi] of the caller's bar.
  explicit Progress(vcg::CallBackPos* cb, int lo = 0, int hi = 100) : cb_(cb), lo_(lo), hi_(hi) {}
  /// Reports `pct` (0..100 of this stage); throttled to 10 Hz unless `force`.
  void operator()(double pct, const char* msg, bool force = false) {
    if (!cb_) return;
    auto now = std::chrono::steady_clock::now();
    if (!force && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    int p = lo_ + int((hi_ - lo_) * (pct < 0 ? 0 : pct > 100 ? 100 : pct) / 100.0);
    cb_(p, msg);
  }
  /// A sub-range [a, b] (in this stage's percent) as a Progress of its own.
  Progress Sub(double a, double b) const {
    return Progress(cb_, lo_ + int((hi_ - lo_) * a / 100.0), lo_ + int((hi_ - lo_) * b / 100.0));
  }

 private:
  vcg::CallBackPos* cb_;
  int lo_, hi_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace vcgext
