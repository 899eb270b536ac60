/// \file coverage.cpp
/// How closely a cage's limit surface follows the input (the interpolating limit's RMS distance
/// and the share of the input's area beyond its outline; the fitted RMS), and the coverage guard
/// that lays a cage out again with more patches when it does not follow the input.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "vcg_ext/core/quad_pairing.h"
#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/cc_fit.h"
#include "vcg_ext/quad/simplify_internal.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext {
namespace simplify_internal {

namespace {

// Share (%) of `input`'s area in triangles none of whose sample points is reached: a point is
// unreached when its closest point on the tessellated limit `tess` (per-vertex `normal`s, scene
// `lim`) lies on a facet along the limit's boundary (`rimFacet`) and is not along the
// interpolated normal there (InterpolationCoverage). Per triangle, as the report's
// UnprojectablePercent (a triangle any normal line hits is reached): a jagged hole's rim
// triangles, partly beyond the smooth limit's outline, do not count. ~20k triangles tested (every
// k-th on large inputs); on small ones each triangle's L x L sub-triangle centroids are its
// samples (L <= 8), on large ones its centroid.
double UnreachedPercent(const TriData& input, const TriData& tess, const std::vector<Vec3>& normal,
                        const std::vector<char>& rimFacet, const EmbreeScene& lim) {
  const int nT = int(input.F.size()), stride = std::max(1, nT / 20000), m = (nT + stride - 1) / stride;
  const int L = std::clamp(int(std::sqrt(20000.0 / std::max(nT, 1))), 1, 8);
  const double tol = 0.0002 * BBoxDiagonal(input.V);
  std::vector<double> total(size_t(m), 0.0), missed(size_t(m), 0.0);  // summed in order below
#pragma omp parallel
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (int s = 0; s < m; ++s) {
      const auto& f = input.F[size_t(s) * stride];
      const Vec3 &a = input.V[f[0]], &b = input.V[f[1]], &c = input.V[f[2]];
      total[s] = 0.5 * (b - a).cross(c - a).norm();
      // sub-triangle centroids in barycentric steps of 1/L: (i + 1/3, j + 1/3) and (i + 2/3, j + 2/3);
      // the report's semantics: the triangle is reached if any part is, so the first reached
      // sample ends its test
      auto reachedAt = [&](double u, double v) {
        const Vec3 x = a + u * (b - a) + v * (c - a);
        const EmbreeScene::Hit h = lim.ClosestPoint(x, std::numeric_limits<double>::infinity(), hint);
        if (!h.valid) return false;
        hint = h.face;
        if (!rimFacet[h.face]) return true;  // inside the limit's outline: its normal line reaches x
        const auto& g = tess.F[h.face];
        Vec3 nrm = (1 - h.u - h.v) * normal[g[0]] + h.u * normal[g[1]] + h.v * normal[g[2]];
        if (nrm.norm() > 0) nrm.normalize();
        const Vec3 d = x - h.point;
        return (d - d.dot(nrm) * nrm).norm() <= std::max(tol, 0.2 * d.norm());
      };
      bool reached = false;
      for (int i = 0; i < L && !reached; ++i)
        for (int j = 0; i + j < L && !reached; ++j)
          for (int up = 0; up < (i + j + 1 < L ? 2 : 1) && !reached; ++up)
            reached = reachedAt((i + (up ? 2.0 : 1.0) / 3) / L, (j + (up ? 2.0 : 1.0) / 3) / L);
      if (!reached) missed[s] = total[s];
    }
  }
  double t = 0, mi = 0;
  for (int s = 0; s < m; ++s) { t += total[s]; mi += missed[s]; }
  return t > 0 ? 100.0 * mi / t : 0.0;
}

}  // namespace

Coverage InterpolationCoverage(const TriData& input, const QuadData& q, bool area) {
  Coverage cov;
  LimitSurface ls = LimitSurface::FromQuads(q);
  if (!ls.Ok() || ls.NumFaces() == 0) return cov;
  const int k = 6;
  TriData tess;
  std::vector<Vec3> normal;
  std::vector<char> rimFacet;  // area: per facet, whether it touches a boundary edge of the cage
  std::map<std::pair<int, int>, int> edgeUse;
  if (area)
    for (const Quad& f : q.F)
      for (int c = 0; c < 4; ++c) ++edgeUse[std::minmax(f[c], f[(c + 1) % 4])];
  tess.V.reserve(size_t(ls.NumFaces()) * (k + 1) * (k + 1));
  for (int f = 0; f < ls.NumFaces(); ++f) {
    const int base = int(tess.V.size());
    // corner c at (0,0), (1,0), (1,1), (0,1) (LimitSurface): edge c is v = 0, u = 1, v = 1, u = 0
    bool rim[4] = {false, false, false, false};
    if (area)
      for (int c = 0; c < 4; ++c) rim[c] = edgeUse[std::minmax(q.F[f][c], q.F[f][(c + 1) % 4])] == 1;
    for (int j = 0; j <= k; ++j)
      for (int i = 0; i <= k; ++i) {
        Vec3 P, Du, Dv;
        ls.Evaluate(f, double(i) / k, double(j) / k, q.V, &P, area ? &Du : nullptr, area ? &Dv : nullptr);
        tess.V.push_back(P);
        if (area) normal.push_back(Du.cross(Dv));
      }
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const int a = base + j * (k + 1) + i;
        tess.F.push_back({a, a + 1, a + k + 2});
        tess.F.push_back({a, a + k + 2, a + k + 1});
        if (area) {
          const char r = (rim[0] && j == 0) || (rim[1] && i == k - 1) || (rim[2] && j == k - 1) || (rim[3] && i == 0);
          rimFacet.push_back(r);
          rimFacet.push_back(r);
        }
      }
  }
  EmbreeScene lim(tess);
  if (!lim.Ok()) return cov;
  const int n = int(input.V.size()), stride = std::max(1, n / 100000), m = (n + stride - 1) / stride;
  std::vector<double> dSq(size_t(m), -1.0);  // summed in order below: the same sum on any thread count
#pragma omp parallel for schedule(static)
  for (int s = 0; s < m; ++s) {
    const Vec3& x = input.V[size_t(s) * stride];
    const EmbreeScene::Hit h = lim.ClosestPoint(x);
    if (h.valid) dSq[s] = (h.point - x).squaredNorm();
  }
  double sum = 0;
  long cnt = 0;
  for (double d : dSq)
    if (d >= 0) { sum += d; ++cnt; }
  cov.rms = cnt ? std::sqrt(sum / double(cnt)) : std::numeric_limits<double>::infinity();
  if (area) cov.unreachedPct = UnreachedPercent(input, tess, normal, rimFacet, lim);
  return cov;
}

double InterpolationRms(const TriData& input, const QuadData& q) { return InterpolationCoverage(input, q, false).rms; }

double FittedRms(const TriData& input, const EmbreeScene& scene, const QuadData& q) {
  const FitResult f = FitCatmullClark(q, input, scene);
  if (!f.error.empty() || f.dataRmsPerIteration.empty()) return std::numeric_limits<double>::infinity();
  return *std::min_element(f.dataRmsPerIteration.begin(), f.dataRmsPerIteration.end());
}

FittedMeasure MeasureFitted(const TriData& input, const EmbreeScene& scene, const QuadData& q, int minSegments,
                            bool unprojectable) {
  FittedMeasure m;
  const FitResult f = FitCatmullClark(q, input, scene);
  if (!f.error.empty()) return m;
  const LimitSurface ls = LimitSurface::FromQuads(f.control);
  if (!ls.Ok() || ls.NumFaces() == 0) return m;
  const int n = AutoMetricSegments(long(input.F.size()), ls.NumFaces(), minSegments);
  const LimitTessellation t = TessellateLimit(ls, f.control.V, n);
  const EmbreeScene limScene(t.mesh);
  m.rms = ReferenceToSurfaceError(input, limScene).first;
  m.folds = FoldedTriangles(t);
  if (unprojectable)
    m.unprojectablePct = UnprojectablePercent(t, limScene, input, scene,
                                              FitBakeParams().maxDistPercent / 100.0 * BBoxDiagonal(input.V));
  return m;
}

double FittedReferenceRms(const TriData& input, const EmbreeScene& scene, const QuadData& q, int minSegments) {
  return MeasureFitted(input, scene, q, minSegments, false).rms;
}

FittedMeasure MeasureAsReported(const TriData& input, const EmbreeScene& scene, const QuadData& quads,
                                bool unprojectable) {
  const QuadData q = LayerRoundTrip(quads);
  if (q.F.empty()) return FittedMeasure();
  return MeasureFitted(input, scene, q, FitBakeParams().limitSegments, unprojectable);
}

QuadSimplifyResult CoverageGuard(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                 const std::vector<double>& S, const std::vector<double>& M,
                                 const QuadSimplifyParams& params, Progress& prog, const std::vector<Quad>* initialQuads,
                                 QuadSimplifyResult r) {
  const double diag = BBoxDiagonal(input.V);
  const bool byRms = params.coverageRmsPermille > 0, byArea = params.coverageUnprojectablePct > 0;
  if (!(byRms || byArea) || !(diag > 0)) return r;
  // how far a cage is from covering: > 1 when a trigger fires (the larger of the two ratios)
  auto excess = [&](double rms, double unproj) {
    return std::max(byRms ? rms / (params.coverageRmsPermille / 1000.0 * diag) : 0.0,
                    byArea ? unproj / params.coverageUnprojectablePct : 0.0);
  };
  const Coverage c0 = byArea || !(r.layoutRms > 0) ? InterpolationCoverage(input, r.quads, byArea) : Coverage{};
  double rms = byRms ? (r.layoutRms > 0 ? r.layoutRms : c0.rms) : 0.0;
  double unproj = byArea ? c0.unreachedPct : 0.0;
  r.layoutUnprojectablePct = byArea ? unproj : -1;
  // The area trigger alone fired: the interpolating limit's outline shrinks inside the rims of a
  // holed scan's many small holes, which the fit pulls back out. Judged as the report will
  // (MeasureAsReported, on when the fitted checks are: coverageFittedPct > 0): a cage whose fitted
  // limit leaves no more than the trigger's own share unreached is kept; one that leaves more is
  // laid out again, each pass judged on its fitted limit too (docs/quad.md "Coverage judged after
  // the fit").
  bool fitted = false;
  if (byArea && params.coverageFittedPct > 0 && excess(rms, 0.0) <= 1 && excess(rms, unproj) > 1) {
    const auto t0 = Clock::now();
    const FittedMeasure fm = MeasureAsReported(input, scene, r.quads, true);
    r.coverageFittedCheckPct = fm.unprojectablePct;
    r.secondsTotal += Since(t0);  // one fit of the input, as the fit filter's
    if (std::isfinite(fm.rms) && fm.unprojectablePct <= params.coverageUnprojectablePct) return r;
    fitted = std::isfinite(fm.rms) && fm.unprojectablePct >= 0;
  }
  // the unreached share the guard judges: the fitted limit's once the cage was fitted
  double judged = fitted ? r.coverageFittedCheckPct : unproj;
  const int maxPatches = std::max(1, int(start.F.size()) / 4);  // half the start's quads
  // The target doubles each time, or, judged on the fitted limit, grows by the square of the
  // excess (the rims' unreached bands narrow as the patches' side, 1/sqrt(patches)) between 1.25x
  // and 2x. A pass can land below its target (on a thin tube one collapse can cascade through the
  // doublets it leaves, cyl_capped: target 48 -> 6 patches), so a pass is kept only when it comes
  // closer to covering the input.
  auto next = [&](int t) {
    const double e = excess(rms, judged), grow = fitted ? std::clamp(e * e, 1.25, 2.0) : 2.0;
    return std::max(t + 1, int(std::lround(grow * t)));
  };
  int target = r.patches;
  const int from = r.patches;
  const double fromRms = rms, fromUnproj = unproj;
  for (int k = 0; k < 8 && excess(rms, judged) > 1 && next(target) <= maxPatches; ++k) {
    target = next(target);
    QuadSimplifyResult g =
        SimplifyOnce(input, start, scene, S, M, LayoutParams(params, target), prog.Sub(90, 100), initialQuads);
    if (!g.error.empty()) break;
    const Coverage gc = InterpolationCoverage(input, g.quads, byArea);
    g.layoutRms = gc.rms;
    const double gUnproj = byArea ? gc.unreachedPct : 0.0;
    double gFitted = -1;  // judged on its fitted limit unless the RMS trigger fires on it
    if (fitted && excess(byRms ? g.layoutRms : 0.0, 0.0) <= 1) {
      const auto t0 = Clock::now();
      gFitted = MeasureAsReported(input, scene, g.quads, true).unprojectablePct;
      g.secondsTotal += Since(t0);
    }
    const double gJudged = gFitted >= 0 ? gFitted : gUnproj;
    r.secondsTotal += g.secondsTotal;
    if (!(excess(byRms ? g.layoutRms : 0.0, gJudged) < excess(rms, judged))) continue;
    g.coverageRelayouts = k + 1;
    g.coverageFromPatches = from;
    g.coverageFromRms = fromRms;
    g.coverageFromUnprojectablePct = fromUnproj;
    g.coverageFittedCheckPct = r.coverageFittedCheckPct;
    g.layoutUnprojectablePct = byArea ? gUnproj : -1;
    g.layoutFittedUnprojectablePct = gFitted;
    g.countPatches = r.countPatches;
    g.countStartFaces = r.countStartFaces;
    g.rejectedByM = r.rejectedByM;
    g.secondsCount = r.secondsCount;
    g.paperLayoutRms = r.paperLayoutRms;
    g.equalizedLayoutRms = r.equalizedLayoutRms;
    g.secondsTotal = r.secondsTotal;
    rms = byRms ? g.layoutRms : 0.0;
    unproj = gUnproj;
    judged = gJudged;
    r = std::move(g);
  }
  r.coverageOutOfRoom = excess(rms, judged) > 1 && next(target) > maxPatches;
  return r;
}

}  // namespace simplify_internal
}  // namespace vcgext
