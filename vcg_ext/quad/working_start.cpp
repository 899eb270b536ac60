/// \file working_start.cpp
/// The first, coarser start of a dense input's simplification and the fall-back to the working
/// resolution (working_start.h).
#include "vcg_ext/quad/working_start.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "vcg_ext/quad/simplify_internal.h"

namespace vcgext {

namespace {

QuadSimplifyResult SimplifyFrom(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
                                const std::vector<double>& M, const QuadSimplifyParams& params, const StartMesh& start,
                                vcg::CallBackPos* cb) {
  if (!start.error.empty()) {
    QuadSimplifyResult r;
    r.error = start.error;
    return r;
  }
  return SimplifyToQuads(input, scene, S, M, params, cb, nullptr, start.differs ? &start.work.mesh : nullptr);
}

// The first start's pass: `params` without the retries that would start over without a budget
// (coverage guard, start refinement, rescue): when one would be needed the working resolution runs
// them (FirstStartRefused). Under a budget with its ladder (kFirstStartBudgetSlack).
QuadSimplifyParams FirstStartPass(QuadSimplifyParams p) {
  p.coverageRmsPermille = 0;
  p.coverageUnprojectablePct = 0;
  p.startRmsPermille = 0;
  p.rescueRmsPermille = 0;
  p.coverageFittedPct = 0;
  return p;
}

// Why the first start's cage `r` (from `startFaces` triangles) is not kept; empty: kept. Without a
// budget also when a retry of `params` would have run: the coverage guard (the interpolating
// limit's RMS or unreached area beyond its triggers) or the start refinement / rescue (its RMS
// beyond their thresholds), judged as they judge.
std::string FirstStartRefused(const TriData& input, const QuadSimplifyParams& params, const QuadSimplifyResult& r,
                              long startFaces) {
  if (!r.error.empty()) return r.error;
  const int target = params.targetPatches;
  char buf[160];
  if (target > 0) {
    if (!(r.patches > kFirstStartBudgetSlack * target)) return {};
    std::snprintf(buf, sizeof buf, "its ladder stopped above %g x the budget", kFirstStartBudgetSlack);
    return buf;
  }
  if (CountBoundedByStart(r.patches, startFaces)) return "its count is above 1/16 of its triangles";
  const double diag = BBoxDiagonal(input.V);
  const bool byArea = params.coverageUnprojectablePct > 0;
  const simplify_internal::Coverage c = simplify_internal::InterpolationCoverage(input, r.quads, byArea);
  // the nearest of the RMS triggers (coverage guard, start refinement, rescue) that are on
  double far = std::numeric_limits<double>::infinity();
  for (const double permille : {params.coverageRmsPermille, params.startRmsPermille, params.rescueRmsPermille})
    if (permille > 0) far = std::min(far, permille / 1000.0 * diag);
  if (c.rms > far) {
    std::snprintf(buf, sizeof buf, "its limit is %.3g per mille from the input (RMS)", 1000 * c.rms / diag);
    return buf;
  }
  if (byArea && c.unreachedPct > params.coverageUnprojectablePct) {
    std::snprintf(buf, sizeof buf, "%.3g %% of the input is beyond its limit", c.unreachedPct);
    return buf;
  }
  return {};
}

}  // namespace

double SliverSharePct(const TriData& m) {
  const double cosLimit = std::cos(kSliverAngleDeg * M_PI / 180.0);
  long slivers = 0;
#pragma omp parallel for reduction(+ : slivers) schedule(static)
  for (long i = 0; i < long(m.F.size()); ++i) {
    const auto& f = m.F[size_t(i)];
    for (int c = 0; c < 3; ++c) {
      const Vec3 u = m.V[f[(c + 1) % 3]] - m.V[f[c]], v = m.V[f[(c + 2) % 3]] - m.V[f[c]];
      const double d = u.norm() * v.norm();
      if (d > 0 && u.dot(v) > cosLimit * d) {
        ++slivers;
        break;
      }
    }
  }
  return m.F.empty() ? 0.0 : 100.0 * double(slivers) / double(m.F.size());
}

WorkingStartResult SimplifyFromWorkingStart(const TriData& input, const EmbreeScene& scene,
                                            const std::vector<double>& S, const std::vector<double>& M,
                                            const QuadSimplifyParams& params, const StartMeshParams& sp,
                                            int firstFaces, vcg::CallBackPos* cb,
                                            const std::vector<Quad>* initialQuads) {
  WorkingStartResult w;
  if (initialQuads) {
    w.result = SimplifyToQuads(input, scene, S, M, params, cb, initialQuads, nullptr);
    return w;
  }
  const long room = params.targetPatches > 0 ? 4L * params.targetPatches : 0;
  const long first = std::max<long>(firstFaces, room);
  const bool dense = firstFaces > 0 && sp.workingFaces > 0 && long(input.F.size()) > sp.workingFaces &&
                     first < sp.workingFaces;
  const auto t0 = std::chrono::steady_clock::now();
  if (dense) {
    StartMeshParams fp = sp;
    fp.workingFaces = int(first);
    w.start = ChooseStartMesh(input, fp, cb);
  }
  // (not decimated, zero-area triangles with coincident corners: the full input with a warning, no
  // coarser than the working resolution's start: none tried)
  if (dense && w.start.work.decimated) {
    w.firstStartFaces = int(w.start.work.mesh.F.size());
    const double slivers = SliverSharePct(w.start.work.mesh), inputSlivers = SliverSharePct(input);
    if (slivers > inputSlivers + kMaxAddedSliverPct) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "%.1f %% of its triangles are slivers, the input's %.1f %%: a part with flat faces",
                    slivers, inputSlivers);
      w.fallbackReason = buf;
    } else {
      w.result = SimplifyFrom(input, scene, S, M, FirstStartPass(params), w.start, cb);
      w.firstPatches = w.result.patches;
      w.fallbackReason = FirstStartRefused(input, params, w.result, w.firstStartFaces);
    }
    w.firstSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (w.fallbackReason.empty()) {
      w.firstKept = true;
      return w;
    }
  }
  w.start = ChooseStartMesh(input, sp, cb);
  w.result = SimplifyFrom(input, scene, S, M, params, w.start, cb);
  return w;
}

}  // namespace vcgext
