/// \file adaptive_parallelism.cpp
/// AdaptiveParallelism (quad_simplify.h): the choice between serial and parallel checks of the
/// simplification's steps, by measured speed per unit of work.
#include <algorithm>

#include "vcg_ext/quad/quad_simplify.h"

namespace vcgext {

bool AdaptiveParallelism::EndBlock(double secondsPerUnit) {
  ++blocks_;
  parallelBlocks_ += par_ ? 1 : 0;
  last_[par_] = secondsPerUnit;
  if (!allowed_) return par_ = false;
  const double other = last_[!par_];
  if (probing_ || confirming_) {  // the block just measured tried this mode (probe, then confirmation)
    const bool wasProbe = probing_;
    probing_ = confirming_ = false;
    sinceProbe_ = 0;
    // a probe must win clearly (block times are noisy); a confirmation only has to be faster
    if (secondsPerUnit < (wasProbe ? 0.85 : 1.0) * other) {
      // a short probe must be confirmed by one regular
      // block: under load a short parallel probe often runs before the other thread is
      // preempted, and looks fast (measured on bunny00 with a busy core: probes 1.0-1.1 us per
      // unit, the regular parallel blocks after them 2.1-2.3, serial 1.7)
      if (wasProbe && par_) confirming_ = true;
      else probe_ = minProbe_;
    } else {
      probe_ = std::min(2 * probe_, maxProbe_);
      Switch(false);
    }
    return par_;
  }
  if (other < 0 || ++sinceProbe_ >= probe_) Switch(true);      // never measured / time to probe
  else if (secondsPerUnit > 1.5 * other) {                      // clearly slower now (load changed):
    Switch(false);
    probe_ = minProbe_;  // the backoff of the old mode's probes does not apply to the new one
  }
  return par_;
}

void AdaptiveParallelism::Switch(bool probe) {
  par_ = !par_;
  probing_ = probe;
  sinceProbe_ = 0;
  ++switches_;
}

}  // namespace vcgext
