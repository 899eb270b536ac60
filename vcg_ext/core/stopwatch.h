#pragma once
/// \file stopwatch.h
/// Wall-clock seconds for the per-stage times every result struct reports (fit, bake,
/// simplification). One definition for the whole library.
#include <chrono>

namespace vcgext {

using Clock = std::chrono::steady_clock;

/// Seconds elapsed since `t` (steady clock).
inline double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace vcgext
