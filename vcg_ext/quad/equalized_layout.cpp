/// \file equalized_layout.cpp
/// The default layout (docs/quad.md "Layout"): the paper's halting counts the patches (the count
/// pass, on a coarse start when the start is large), the S-cost layout pass spends that count,
/// and when the count ran on the real start the closer of the two cages is kept. With two threads
/// the count pass runs beside the layout pass (quad::LayoutGate); the cages are the sequential
/// ones bit for bit.
#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <thread>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "vcg_ext/core/decimate.h"
#include "vcg_ext/quad/simplify_internal.h"
#include "vcg_ext/quad/working_start.h"

namespace vcgext {
namespace simplify_internal {

DecimateResult CountStart(const TriData& start, int countFaces) {
  WorkingResolutionParams wp;
  wp.maxFaces = countFaces;
  DecimateResult coarse = WorkingResolution(start, wp);
  if (coarse.decimated && SliverSharePct(coarse.mesh) > SliverSharePct(start) + kMaxAddedSliverPct)
    coarse.decimated = false;
  return coarse;
}

namespace {

// What every pass of the equalized layout shares: the input, its scene and Fitmaps, the start.
struct Passes {
  const TriData& input;
  const TriData& start;
  const EmbreeScene& scene;
  const std::vector<double>& S;
  const std::vector<double>& M;
  const std::vector<Quad>* initialQuads;
  QuadSimplifyResult Run(const TriData& from, const QuadSimplifyParams& p, Progress prog,
                         quad::LayoutGate* gate = nullptr, bool* cancelled = nullptr, double* gateWait = nullptr,
                         quad::LayoutGate* publishTo = nullptr) const {
    return SimplifyOnce(input, from, scene, S, M, p, prog, initialQuads, gate, cancelled, gateWait, publishTo);
  }
};

// The count pass: the paper's halting (its cost, no valence term), on a coarse start when
// `decimate`.
struct Count {
  QuadSimplifyParams params;
  bool decimate = false;   // counted on `coarse`, the start decimated to countFaces triangles
  DecimateResult coarse;
  QuadSimplifyResult c;
  bool counted = false;    // c holds the count pass (or its error)
  bool recounted = false;  // c holds the count pass on `start` after one on `coarse` (the worker's recount)
  double overlap = 0;      // seconds of the count pass hidden behind the layout pass
  void DecimateStart(const TriData& start, int countFaces) { coarse = CountStart(start, countFaces); }
};

// The count pass on the second thread (serial checks), publishing to `gate`: returns the count
// the layout pass is to reach (-1: none, the layout pass is cancelled).
int CountBeside(const Passes& ps, const QuadSimplifyParams& params, Count& k, quad::LayoutGate& gate) {
  int target = -1;
  try {
    QuadSimplifyParams wcp = k.params;
    wcp.parallelChecks = QuadSimplifyParams::ParallelChecks::Never;
    // the count on the layout pass's own start, publishing its live count for the layout pass to follow
    auto countOnStart = [&] { return ps.Run(ps.start, wcp, Progress(nullptr), nullptr, nullptr, nullptr, &gate); };
    if (k.decimate) k.DecimateStart(ps.start, params.countFaces);
    if (!k.decimate || !k.coarse.decimated) {
      // A coarse start CountStart refused (slivers): the layout pass, which went on freely while
      // it was decimated, stops where it is and follows this count's live count.
      if (k.decimate) gate.RaiseFloor(std::numeric_limits<int>::max());
      k.c = countOnStart();
      k.counted = true;
    } else {
      k.c = ps.Run(k.coarse.mesh, wcp, Progress(nullptr));
      k.counted = true;
      // A count the coarse start bounds is counted again on the real start, here, while the
      // layout pass goes on down to a bound of the recount (recountFloorFactor x the coarse
      // count) or, when it is already below that, waits where it is, and then follows the
      // recount's live count.
      if (k.c.error.empty() && CountBoundedByStart(k.c.patches, long(k.coarse.mesh.F.size()))) {
        gate.RaiseFloor(params.recountFloorFactor * k.c.patches);
        k.c = countOnStart();
        k.recounted = true;
      }
    }
    if (k.c.error.empty()) target = std::max(1, k.c.patches);
  } catch (const std::exception& e) {
    k.c = QuadSimplifyResult();
    k.c.error = std::string("count pass: ") + e.what();
    k.counted = true;
  }
  return target;
}

// The two passes overlap (docs/quad.md "Layout"): the layout pass needs the count only at its
// end, so with two threads the count pass (decimation included) runs on a second thread with
// serial checks while the layout pass runs here (quad::LayoutGate). On a coarse count start the
// layout pass goes on down to the largest count that needs no recount (countFaces / 16) and
// waits there for the count; a count that needs a recount raises that floor to
// recountFloorFactor x itself (or to where the layout pass is, if lower) and recounts on the
// second thread too. A count on the layout pass's own start (a small start, the recount, or a
// coarse start CountStart refused) lets the layout pass go on while it stays above that pass's live count. A count below a step
// the layout pass has taken, or an error, cancels it, and the rest runs in sequence. The cages
// are the same as in sequence (no step depends on the threads).
// Returns the layout pass (patches 0 when it is to be laid out again after the count), or the
// error of either pass.
QuadSimplifyResult LayoutBesideCount(const Passes& ps, const QuadSimplifyParams& params, Count& k, Progress& prog) {
  // (no floor on the count's own start: only its live count lets the layout pass go on)
  quad::LayoutGate gate(k.decimate ? std::max(1, params.countFaces / 16) : std::numeric_limits<int>::max());
  double countWall = 0;
  std::thread worker([&] {
    const auto w0 = Clock::now();
    const int target = CountBeside(ps, params, k, gate);
    countWall = Since(w0);
    gate.Set(target);
  });
  bool cancelled = false;
  double gateWait = 0;
  QuadSimplifyResult res;
  try {
    res = ps.Run(ps.start, LayoutParams(params, 0), prog.Sub(0, 100), &gate, &cancelled, &gateWait);
  } catch (...) {
    worker.join();  // it never waits for this thread
    throw;
  }
  const auto j0 = Clock::now();
  worker.join();
  const double joinWait = Since(j0);
  if (k.counted && !k.c.error.empty()) return k.c;
  if (!res.error.empty()) return res;
  if (!cancelled && gate.Target() > 0) {
    res.secondsSimplify -= gateWait;  // the wait inside the layout pass is the count's
    res.secondsTotal -= gateWait;
    k.overlap = std::max(0.0, countWall - gateWait - joinWait);
  } else {
    // laid out again below, after the recount; also when the layout pass ended (no collapse
    // left) before the cancellation reached it: the recount may stop above where it ended
    res = QuadSimplifyResult();
  }
  return res;
}

// The count pass's set-up (docs/quad.md "Layout"): the paper's halting without the valence term,
// on a decimated start when the start has more than 1.25 countFaces triangles; given quads are
// counted as they are.
Count CountSetUp(const TriData& start, const QuadSimplifyParams& params, const std::vector<Quad>* initialQuads) {
  Count k;
  k.decimate = !(initialQuads && !initialQuads->empty()) && params.countFaces > 0 &&
               int(start.F.size()) > params.countFaces + params.countFaces / 4;
  k.params = params;
  k.params.layout = QuadSimplifyParams::Layout::PaperHalting;
  k.params.valenceWeight = 0;  // the paper's count
  return k;
}

// The count pass where LayoutBesideCount did not run it (on `countStart`), and again on the real
// start when `countStart` bounded it: a count above 1/16 of the coarse start's triangles (its
// quads reduced less than 8x). Returns whether the count is the real start's recount; k.c holds
// the error of a pass that failed.
bool FinishCount(const Passes& ps, const TriData& countStart, Count& k, Progress& prog) {
  QuadSimplifyResult& c = k.c;
  if (!k.counted) {
    c = ps.Run(countStart, k.params, prog.Sub(0, 30));
    if (!c.error.empty()) return false;
  }
  const bool recount =
      k.recounted || (&countStart != &ps.start && CountBoundedByStart(c.patches, long(countStart.F.size())));
  if (recount && !k.recounted) c = ps.Run(ps.start, k.params, prog.Sub(0, 30));
  return recount;
}

// When the count pass `c` ran on the real start mesh it is the paper's own result: whichever of
// the two cages' interpolating limits follows the input more closely is kept (docs/quad.md
// "Layout"). True when that is the paper's (`res` is then it, timed from t0).
bool KeepPaperLayout(const TriData& input, const TriData& start, Clock::time_point t0, QuadSimplifyResult& c,
                     QuadSimplifyResult& res) {
  res.layoutRms = InterpolationRms(input, res.quads);
  c.layoutRms = InterpolationRms(input, c.quads);
  res.paperLayoutRms = c.layoutRms;
  if (!(c.layoutRms < res.layoutRms)) {
    res.equalizedLayoutRms = res.layoutRms;
    return false;
  }
  const double eqRms = res.layoutRms;
  res = std::move(c);
  res.paperLayoutRms = res.layoutRms;
  res.equalizedLayoutRms = eqRms;
  res.keptPaperLayout = true;
  res.countPatches = res.patches;
  res.countStartFaces = int(start.F.size());
  // (the stages then sum to the wall time: "count pass" is what the other passes added, beside
  // this one or after it)
  const double own = res.secondsTotal;
  res.secondsTotal = std::chrono::duration<double>(Clock::now() - t0).count();
  res.secondsCount = std::max(0.0, res.secondsTotal - own);
  return true;
}

}  // namespace

QuadSimplifyResult EqualizedLayout(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                   const std::vector<double>& S, const std::vector<double>& M,
                                   const QuadSimplifyParams& params, Progress& prog,
                                   const std::vector<Quad>* initialQuads) {
  const Passes ps{input, start, scene, S, M, initialQuads};
  const auto t0 = Clock::now();
  Count k = CountSetUp(start, params, initialQuads);
  QuadSimplifyResult res;
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  if (threads >= 2 && params.parallelChecks != QuadSimplifyParams::ParallelChecks::Never) {
    res = LayoutBesideCount(ps, params, k, prog);
    if (!res.error.empty()) return res;
  } else if (k.decimate) {
    k.DecimateStart(start, params.countFaces);
  }
  QuadSimplifyResult& c = k.c;
  const TriData& countStart = k.decimate && k.coarse.decimated ? k.coarse.mesh : start;
  const bool recount = FinishCount(ps, countStart, k, prog);
  if (!c.error.empty()) return c;
  if (res.patches == 0)  // not laid out beside the count
    res = ps.Run(start, LayoutParams(params, std::max(1, c.patches)), prog.Sub(30, 100));
  if (!res.error.empty()) return res;
  if ((recount || &countStart == &start) && KeepPaperLayout(input, start, t0, c, res)) return res;
  res.countPatches = c.patches;
  res.countStartFaces = int((recount ? start : countStart).F.size());
  res.rejectedByM = c.rejectedByM;
  res.secondsCount = std::chrono::duration<double>(Clock::now() - t0).count() - res.secondsTotal;
  res.secondsCountOverlapped = k.overlap;
  res.secondsTotal += res.secondsCount;
  return res;
}

}  // namespace simplify_internal
}  // namespace vcgext
