// S- and M-Fitmaps (Panozzo et al. 2011, §3.1.2–3.1.3). Design and decisions: docs/fitmaps.md.
// This file: the per-vertex fitmaps from the evaluations' radius values, Fast mode's plan over the
// vertex hierarchy, Reference mode and the working resolution; one vertex's evaluation is in
// fitmaps_site.cpp, the hierarchy and normals in fitmaps_hierarchy.cpp (fitmaps_eval.h).
#include "vcg_ext/fitmaps/fitmaps.h"

#include "vcg_ext/core/decimate.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>

#include "vcg_ext/core/progress.h"
#include "vcg_ext/fitmaps/fitmaps_eval.h"

namespace vcgext {

using namespace fitmaps_internal;  // NOLINT (source file only)

namespace {

/// a^{1/4} of the least-squares fit E = a r^4 (closed form a = sum E r^4 / sum r^8), computed
/// with radii relative to r_h to avoid overflow. Returns 0 when no radius was usable.
double SFromE(const std::vector<double>& radii, const RadiusValues& rv, bool& ok) {
  const double rh = radii.back();
  double num = 0, den = 0;
  ok = false;
  for (size_t i = 0; i < radii.size(); ++i) {
    if (!rv.eOk[i]) continue;
    const double q = radii[i] / rh, q4 = q * q * q * q;
    num += rv.E[i] * q4;
    den += q4 * q4;
    ok = true;
  }
  if (!ok || !(den > 0)) return 0.0;
  const double a = std::max(0.0, num / den) / (rh * rh * rh * rh);  // unit length^-3
  const double s = std::pow(a, 0.25);
  return std::isfinite(s) ? s : 0.0;
}

void Keep(const FitmapParams& p, const RadiusValues& rv, int v, FitmapResult& res) {
  if (!p.keepPerRadius) return;
  const size_t H = rv.E.size();
  for (size_t i = 0; i < H; ++i) {
    res.perRadiusE[v * H + i] = rv.eOk[i] ? rv.E[i] : -1.0;
    res.perRadiusFlipped[v * H + i] = rv.phiOk[i] ? rv.phi[i] : -1.0;
  }
}

/// F_M: the largest r_i such that r_1..r_i all have a flipped share below tau; at least r_0.
double MFromPhi(const Context& ctx, const RadiusValues& rv) {
  double M = ctx.radii[0];
  for (size_t i = 1; i < ctx.radii.size(); ++i) {
    if (!rv.phiOk[i] || !(rv.phi[i] < ctx.tau)) break;
    M = ctx.radii[i];
  }
  return M;
}

}  // namespace

namespace {
// Fitmaps of a dense mesh from its working resolution M': computed on M', then interpolated at
// each vertex's closest point on M'. Unreferenced vertices get S = 0, M = r_0 as usual.
FitmapResult FitmapsFromWorkingResolution(const TriData& input, const FitmapParams& p, vcg::CallBackPos* cb) {
  const auto t0 = std::chrono::steady_clock::now();
  WorkingResolutionParams wp;
  wp.maxFaces = p.workingFaces;
  DecimateResult d = WorkingResolution(input, wp, cb);
  FitmapResult res;
  EmbreeScene coarseScene(d.mesh);
  if (!coarseScene.Ok()) { res.error = "ray-casting scene of the working resolution: " + coarseScene.Error(); return res; }
  FitmapParams q = p;
  q.workingFaces = 0;
  FitmapResult c = ComputeFitmaps(d.mesh, coarseScene, q, cb);
  if (!c.error.empty()) return c;
  const auto t1 = std::chrono::steady_clock::now();
  const int n = int(input.V.size());
  res.S.assign(n, 0.0);
  res.M.assign(n, c.radii.empty() ? 0.0 : c.radii.front());
  res.computed.assign(n, 0);
  std::vector<char> used(n, 0);
  for (const auto& f : input.F)
    for (int v : f) used[v] = 1;
#pragma omp parallel
  {
    int hint = -1;  // the previous vertex's face (ClosestPoint's hint: neighbouring vertices)
#pragma omp for schedule(dynamic, 4096)
    for (int i = 0; i < n; ++i) {
      if (!used[i]) continue;
      EmbreeScene::Hit h = coarseScene.ClosestPoint(input.V[i], std::numeric_limits<double>::infinity(), hint);
      if (!h.valid) continue;
      hint = h.face;
      const Tri& t = d.mesh.F[h.face];
      const double w0 = 1.0 - h.u - h.v;
      res.S[i] = w0 * c.S[t[0]] + h.u * c.S[t[1]] + h.v * c.S[t[2]];
      res.M[i] = w0 * c.M[t[0]] + h.u * c.M[t[1]] + h.v * c.M[t[2]];
      res.computed[i] = 1;
    }
  }
  for (char u : used) res.unreferenced += u ? 0 : 1;
  res.radii = c.radii;
  res.fallbackNormals = c.fallbackNormals;
  res.noFit = c.noFit;
  res.levels = c.levels;
  res.workingFaces = int(d.mesh.F.size());
  res.secondsDecimate = d.seconds;
  if (d.zeroAreaFlips > 0)
    res.notes.push_back(std::to_string(d.zeroAreaFlips) +
                        " edge flips removed zero-area triangles from the decimated copy (the layer is unchanged)");
  if (d.skippedDegenerate)
    res.warnings.push_back("zero-area triangles with coincident corners: computed on all " +
                           std::to_string(input.F.size()) +
                           " triangles instead of a decimated copy (slower; Filters > Cleaning and Repairing > "
                           "Remove Zero Area Faces avoids it)");
  res.secondsTransfer = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}
}  // namespace

namespace {

// ComputeFitmaps' argument checks, in order: the first problem, or empty.
std::string CheckFitmapInputs(const TriData& input, const EmbreeScene& scene, const FitmapParams& p) {
  const int nV = int(input.V.size());
  if (nV == 0) return "the mesh is empty (no vertices)";
  if (input.F.empty()) return "the mesh has no faces (point cloud): a triangle mesh is needed";
  for (size_t i = 0; i < input.V.size(); ++i)
    if (!input.V[i].allFinite()) return "vertex " + std::to_string(i) + " has NaN or infinite coordinates";
  for (size_t i = 0; i < input.V.size(); ++i)
    if (input.V[i].cwiseAbs().maxCoeff() > kMaxCoordinate) {
      return "vertex " + std::to_string(i) + " has a coordinate beyond 1e17, more than the ray caster can represent: scale the mesh down";
    }
  int badIdx = 0;
  for (const auto& f : input.F)
    for (int c : f) badIdx += (c < 0 || c >= nV) ? 1 : 0;
  if (badIdx) return std::to_string(badIdx) + " face corners refer to no vertex (index out of range)";
  if (!(p.tauPercent >= 0 && p.tauPercent <= 100)) return "tau must be in [0, 100] percent";
  if (p.numRadii < 1 || p.numRadii > 64) return "the number of radii must be in [1, 64]";
  if (!(p.maxRadiusPercent > 0 && p.maxRadiusPercent <= 100)) {
    return "the largest radius must be in (0, 100] percent of the bbox diagonal";
  }
  if (!(p.minRadiusPercent >= 0 && p.minRadiusPercent <= p.maxRadiusPercent)) {
    return "the smallest radius must be in [0, largest radius] percent of the bbox diagonal";
  }
  if (!(p.referenceSampleFactor > 0 && p.referenceSampleFactor <= 1e4)) {
    return "referenceSampleFactor must be in (0, 10000]";
  }
  if (p.minFitPoints < 1) return "minFitPoints must be at least 1";
  for (int v : p.vertices)
    if (v < 0 || v >= nV) return "vertex subset: index " + std::to_string(v) + " is out of range";
  if (!scene.Ok()) return "ray-casting scene: " + scene.Error();
  if (scene.Mesh().V.size() != input.V.size() || scene.Mesh().F.size() != input.F.size()) {
    return "the ray-casting scene was not built on this mesh";
  }
  if (p.workingFaces < 0) return "the working resolution must be >= 0 triangles";
  return {};
}

// Vertices in Morton (Z-curve) order, so that the traversals touch nearby memory: order[k] is
// the caller's vertex of rank k, rank its inverse (the results are mapped back; faces keep their
// order, so the Embree scene stays valid).
void MortonOrder(const std::vector<Vec3>& V, std::vector<int>& order, std::vector<int>& rank) {
  const int nV = int(V.size());
  order.resize(nV);
  rank.resize(nV);
  Vec3 lo = V[0], hi = V[0];
  for (const auto& q : V) { lo = lo.cwiseMin(q); hi = hi.cwiseMax(q); }
  const double ext = std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<std::pair<uint64_t, int>> code(nV);
  auto spread = [](uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  };
  for (int i = 0; i < nV; ++i) {
    const Vec3 t = (V[i] - lo) / ext * 2097151.0;
    code[i] = {spread(uint64_t(t[0])) | spread(uint64_t(t[1])) << 1 | spread(uint64_t(t[2])) << 2, i};
  }
  std::sort(code.begin(), code.end());
  for (int k = 0; k < nV; ++k) { order[k] = code[k].second; rank[code[k].second] = k; }
}

// S and M of vertex v (and its per-radius values when kept) from its radius values; false when
// the S fit failed.
bool StoreVertex(const Context& ctx, const RadiusValues& rv, int v, FitmapResult& res) {
  bool ok;
  res.S[v] = SFromE(ctx.radii, rv, ok);
  res.M[v] = MFromPhi(ctx, rv);
  Keep(*ctx.p, rv, v, res);
  return ok;
}

// Reference mode (paper §3.1 literally): every vertex of `todo`, all radii, on the mesh itself.
// Returns the vertices whose S fit failed.
int ReferenceValues(Context& ctx, const Level& fine, const std::vector<int>& todo, FitmapResult& res,
                    Progress& prog) {
  const TriData& m = *ctx.m;
  const int nV = int(m.V.size()), H = int(ctx.radii.size());
  std::atomic<long> done{0};
  int noFit = 0;
  ctx.vf = VertexFaceAdjacency(m.F, nV);
#pragma omp parallel reduction(+ : noFit)
  {
    Scratch s;
    RadiusValues rv;
#pragma omp for schedule(dynamic, 4)
    for (long k = 0; k < long(todo.size()); ++k) {
      const int v = todo[k];
      rv.Init(H);
      EvalSpec e;
      e.start = e.vertex = v;
      e.literal = true;
      Evaluate(ctx, fine, e, 0, H, s, rv);
      if (!StoreVertex(ctx, rv, v, res)) ++noFit;
      ++done;
      if (omp_get_thread_num() == 0) prog(100.0 * done / todo.size(), "Fitmaps (reference)");
    }
  }
  return noFit;
}

// The 10th percentile of the vertex areas (a third of the faces' around each; vertices with none
// left out): the area per point where the mesh is dense (0 for a mesh without area).
double DenseVertexArea(const TriData& m, const std::vector<double>& faceArea) {
  std::vector<double> a(m.V.size(), 0.0);
  for (size_t f = 0; f < m.F.size(); ++f)
    for (int v : m.F[f]) a[size_t(v)] += faceArea[f] / 3;
  a.erase(std::remove_if(a.begin(), a.end(), [](double x) { return !(x > 0); }), a.end());
  if (a.empty()) return 0;
  std::nth_element(a.begin(), a.begin() + long(a.size() / 10), a.end());
  return a[a.size() / 10];
}

// Fast mode's plan: the hierarchy of levels (level 0 = the mesh), for each radius the coarsest
// level whose neighbourhood of that radius still holds about fastPointsPerFit points, and which
// radii get their S fitted per vertex (on level levelS) instead of interpolated; a radius whose
// ball would hold far more than its target where the mesh is densest leaves level 0
// (FitmapParams::fastDenseBallFactor).
struct FastPlan {
  std::vector<Level> levels;
  std::vector<int> levelOf, levelS;
  std::vector<char> perVertexS;
};
FastPlan PlanFastLevels(const Context& ctx, Level fine, double r0, double rh) {
  const TriData& m = *ctx.m;
  const FitmapParams& p = *ctx.p;
  const int H = int(ctx.radii.size());
  FastPlan plan;
  std::vector<Level>& levels = plan.levels;
  levels.push_back(std::move(fine));
  BuildClusterFaces(m, ctx.faceArea, levels[0]);
  const double target = std::max(16, p.fastPointsPerFit);
  const double dense = DenseVertexArea(m, ctx.faceArea);
  // whether the ball of radius r on level 0 holds more than fastDenseBallFactor * points where
  // the mesh is densest (FitmapParams::fastDenseBallFactor)
  auto tooDense = [&](double r, double points) {
    return p.fastDenseBallFactor > 0 && dense > 0 && M_PI * r * r / dense > p.fastDenseBallFactor * points;
  };
  std::vector<int>& levelOf = plan.levelOf;
  levelOf.assign(H, 0);
  for (int i = 0; i < H; ++i) {
    const double r = ctx.radii[i];
    const bool coarser = tooDense(r, target);
    int l = 0;
    while (true) {
      if (int(levels.size()) <= l + 1) {
        const Level& f = levels.back();
        if (f.X.size() < 64 || levels.size() >= 16) break;
        const double cover = r0 * std::pow(2.0, 0.5 * double(levels.size()));
        Level c = Coarsen(f, cover);
        c.areaPerPoint = ctx.totalArea / double(c.X.size());
        c.index = int(levels.size());
        BuildClusterFaces(m, ctx.faceArea, c);
        levels.push_back(std::move(c));
      }
      const Level& nx = levels[l + 1];
      if (M_PI * r * r / nx.areaPerPoint >= target || (l == 0 && coarser)) ++l; else break;
    }
    levelOf[i] = l;
  }
  // E(r_i) enters a with weight (r_i/r_h)^4: radii below r_h/2.5 weigh < 2.6% each (and their
  // E is much smaller than E(r_h)), so they
  // are interpolated from the level points like the flipped shares; the larger ones are
  // fitted per vertex in the vertex's own frame (the frame matters most there).
  plan.perVertexS.assign(H, 0);
  plan.levelS.assign(H, 0);
  for (int i = 0; i < H; ++i) {
    if (levelOf[i] == 0 || ctx.radii[i] < rh / 2.5) continue;
    plan.perVertexS[i] = 1;
    // the per-vertex S fits use more points than the M estimates (fastPointsPerSFit)
    const double r = ctx.radii[i];
    const double points = std::max(16, p.fastPointsPerSFit);
    int l = 0;
    while (l + 1 < int(levels.size()) &&
           (M_PI * r * r / levels[l + 1].areaPerPoint >= points || (l == 0 && tooDense(r, points))))
      ++l;
    plan.levelS[i] = l;
  }
  return plan;
}

// Fast mode, coarse levels: every level point, all radii of that level (values[l][q]).
std::vector<std::vector<RadiusValues>> CoarseValues(const Context& ctx, const FastPlan& plan) {
  const int H = int(ctx.radii.size());
  std::vector<std::vector<RadiusValues>> coarse(plan.levels.size());
  for (size_t l = 1; l < plan.levels.size(); ++l) {
    int i0 = H, i1 = 0;
    for (int i = 0; i < H; ++i)
      if (plan.levelOf[i] == int(l)) { i0 = std::min(i0, i); i1 = std::max(i1, i + 1); }
    if (i0 >= i1) continue;
    const Level& lv = plan.levels[l];
    coarse[l].resize(lv.X.size());
#pragma omp parallel
    {
      Scratch s;
#pragma omp for schedule(dynamic, 8)
      for (long q = 0; q < long(lv.X.size()); ++q) {
        coarse[l][q].Init(H);
        EvalSpec e;
        e.start = int(q);
        e.vertex = lv.fineIdx[q];
        e.doS = true;  // used where S is not fitted per vertex (radii below r_h / 6)
        e.stopMAtFailure = false;
        Evaluate(ctx, lv, e, i0, i1, s, coarse[l][q]);
      }
    }
  }
  return coarse;
}

// Calls fn(cc, w) for the point cc of level lv that stands for fine vertex v (its cluster), then
// for each neighbour of it, with the interpolation weight w = exp(-d^2 / (2 * area per point)), d
// the distance from x (v's position) to the point.
template <class Fn>
void ForNearPoints(const Level& lv, int v, const Vec3& x, Fn&& fn) {
  const int c = lv.ofFine[v];
  const double inv = 1.0 / (2.0 * lv.areaPerPoint);
  auto take = [&](int cc) { fn(cc, std::exp(-(lv.X[cc] - x).squaredNorm() * inv)); };
  take(c);
  for (const int* it = lv.adj.Begin(c); it != lv.adj.End(c); ++it) take(*it);
}

// The large-radius S fits of fine vertex v in rv, interpolated from those at the points of level
// sLevel (sVals), for the radii fitted per vertex (FastPlan::perVertexS).
void InterpolateLargeS(const FastPlan& plan, int sLevel, const std::vector<RadiusValues>& sVals, int v,
                       const Vec3& x, RadiusValues& rv) {
  const Level& lv = plan.levels[sLevel];
  for (int i = 0; i < int(plan.perVertexS.size()); ++i) {
    if (!plan.perVertexS[i]) continue;
    double we = 0, se = 0;
    ForNearPoints(lv, v, x, [&](int cc, double w) {
      if (!sVals[cc].eOk[i]) return;
      we += w;
      se += w * sVals[cc].E[i];
    });
    if (we > 0) { rv.E[i] = se / we; rv.eOk[i] = 1; }
  }
}

// The coarse radii [i1fine, H) of fine vertex v in rv, interpolated from their levels' points
// (`coarse`): E where it is not fitted per vertex, phi when `needM`.
void InterpolateCoarse(const FastPlan& plan, const std::vector<std::vector<RadiusValues>>& coarse, int i1fine,
                       bool needM, int v, const Vec3& x, RadiusValues& rv) {
  for (int i = i1fine; i < int(plan.levelOf.size()); ++i) {
    const auto& vals = coarse[plan.levelOf[i]];
    double wp = 0, sp = 0, we = 0, se = 0;
    ForNearPoints(plan.levels[plan.levelOf[i]], v, x, [&](int cc, double w) {
      if (vals[cc].phiOk[i]) { wp += w; sp += w * vals[cc].phi[i]; }
      if (vals[cc].eOk[i]) { we += w; se += w * vals[cc].E[i]; }
    });
    if (we > 0 && !plan.perVertexS[i]) { rv.E[i] = se / we; rv.eOk[i] = 1; }
    if (wp > 0 && needM) { rv.phi[i] = sp / wp; rv.phiOk[i] = 1; }
  }
}

// The per-vertex S fits of the large radii (FastPlan::perVertexS) in the frame of fine vertex v,
// each run of radii on one level evaluated together.
void FitLargeS(const Context& ctx, const FastPlan& plan, int v, Scratch& s, RadiusValues& rv) {
  const int H = int(ctx.radii.size());
  EvalSpec ec;
  ec.vertex = v;
  ec.doM = false;
  for (int i = 0; i < H;) {
    if (!plan.perVertexS[i]) { ++i; continue; }
    int j = i;
    while (j < H && plan.perVertexS[j] && plan.levelS[j] == plan.levelS[i]) ++j;
    ec.start = plan.levels[plan.levelS[i]].ofFine[v];
    Evaluate(ctx, plan.levels[plan.levelS[i]], ec, i, j, s, rv);
    i = j;
  }
}

// Fast mode, per vertex of `todo`: the fine-level radii, the large-radius S fits (per vertex or
// interpolated from level sLevel's points) and the coarse radii interpolated from `coarse`.
// Returns the vertices whose S fit failed.
int FastValues(const Context& ctx, const FastPlan& plan, const std::vector<std::vector<RadiusValues>>& coarse,
               const std::vector<int>& todo, FitmapResult& res, Progress& prog,
               std::chrono::steady_clock::time_point t0) {
  const TriData& m = *ctx.m;
  const FitmapParams& p = *ctx.p;
  const int H = int(ctx.radii.size());
  std::atomic<long> done{0};
  int noFit = 0;
  // large-radius S fits in the frames of the points of level sLevel (0: every vertex)
  const int sLevel = std::clamp(p.fastSLevel, 0, int(plan.levels.size()) - 1);
  std::vector<RadiusValues> sVals;
  if (sLevel > 0) {
    const Level& lv = plan.levels[sLevel];
    sVals.resize(lv.X.size());
#pragma omp parallel
    {
      Scratch s;
#pragma omp for schedule(dynamic, 16)
      for (long q = 0; q < long(lv.X.size()); ++q) {
        sVals[q].Init(H);
        FitLargeS(ctx, plan, lv.fineIdx[q], s, sVals[q]);
      }
    }
  }
  prog(30, "Fitmaps: vertices", true);
  res.secondsCoarse = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // fine level per vertex + interpolation of the coarse radii
  int i1fine = 0;
  while (i1fine < H && plan.levelOf[i1fine] == 0) ++i1fine;
#pragma omp parallel reduction(+ : noFit)
  {
    Scratch s;
    RadiusValues rv;
#pragma omp for schedule(dynamic, 32)
    for (long k = 0; k < long(todo.size()); ++k) {
      const int v = todo[k];
      rv.Init(H);
      EvalSpec e;
      e.start = e.vertex = v;
      Evaluate(ctx, plan.levels[0], e, 0, i1fine, s, rv);
      if (sLevel == 0) FitLargeS(ctx, plan, v, s, rv);
      bool needM = true;
      for (int i = 1; i < i1fine; ++i)
        if (!(rv.phiOk[i] && rv.phi[i] < ctx.tau)) needM = false;
      if (ctx.normals[v].squaredNorm() > 0) {
        if (sLevel > 0) InterpolateLargeS(plan, sLevel, sVals, v, m.V[v], rv);
        InterpolateCoarse(plan, coarse, i1fine, needM, v, m.V[v], rv);
      }
      if (!StoreVertex(ctx, rv, v, res)) ++noFit;
      ++done;
      if (omp_get_thread_num() == 0) prog(30 + 70.0 * done / todo.size(), "Fitmaps");
    }
  }
  return noFit;
}

// The input with its vertices in Morton order (MortonOrder: order[k] is the input vertex at k,
// rank its inverse), the faces renumbered.
TriData MortonOrdered(const TriData& input, std::vector<int>& order, std::vector<int>& rank) {
  const int nV = int(input.V.size());
  MortonOrder(input.V, order, rank);
  TriData mm;
  mm.V.resize(nV);
  for (int k = 0; k < nV; ++k) mm.V[k] = input.V[order[k]];
  mm.F = input.F;
  for (auto& f : mm.F)
    for (int& c : f) c = rank[c];
  return mm;
}

// The vertices to compute (FitmapParams::vertices as Morton ranks, sorted and unique; every
// vertex when empty), with res's per-vertex arrays sized and set for them (M = r_0, the paper's
// grid; `unreferenced` counted from the adjacency vv).
std::vector<int> VerticesToCompute(const Context& ctx, const std::vector<int>& rank, const Adjacency& vv,
                                   FitmapResult& res) {
  const FitmapParams& p = *ctx.p;
  const int nV = int(ctx.m->V.size()), H = int(ctx.radii.size());
  std::vector<int> todo;
  for (int v : p.vertices) todo.push_back(rank[v]);
  std::sort(todo.begin(), todo.end());
  todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
  if (todo.empty()) {
    todo.resize(nV);
    for (int i = 0; i < nV; ++i) todo[i] = i;
  }
  res.S.assign(nV, 0.0);
  res.M.assign(nV, 0.0);
  res.computed.assign(nV, 0);
  for (int v : todo) {
    res.computed[v] = 1;
    res.M[v] = ctx.radii[0];  // r_0 on the paper's grid
  }
  if (p.keepPerRadius) {
    res.perRadiusE.assign(size_t(nV) * H, -1.0);
    res.perRadiusFlipped.assign(size_t(nV) * H, -1.0);
  }
  for (int v : todo) res.unreferenced += vv.Count(v) == 0 ? 1 : 0;
  return todo;
}

// res's per-vertex arrays back from Morton order to the caller's (order: MortonOrdered's).
void ToCallerOrder(const std::vector<int>& order, int H, FitmapResult& res) {
  const int nV = int(order.size());
  auto unpermute = [&](auto& vec, size_t stride) {
    if (vec.empty()) return;
    auto tmp = vec;
    for (int k = 0; k < nV; ++k)
      for (size_t j = 0; j < stride; ++j) vec[size_t(order[k]) * stride + j] = tmp[size_t(k) * stride + j];
  };
  unpermute(res.S, 1);
  unpermute(res.M, 1);
  unpermute(res.computed, 1);
  unpermute(res.perRadiusE, size_t(H));
  unpermute(res.perRadiusFlipped, size_t(H));
}

}  // namespace

std::vector<double> FitmapRadii(double r0, double rh, double diag, const FitmapParams& p) {
  std::vector<double> radii;
  if (p.minRadiusPercent > 0) {
    const double floor = std::max(r0, p.minRadiusPercent / 100.0 * diag) * (1 - 1e-9);
    for (double r = rh; r >= floor && radii.size() < 64; r /= kAnchoredRadiusRatio) radii.push_back(r);
    if (radii.empty()) radii.push_back(rh);
    std::reverse(radii.begin(), radii.end());
    return radii;
  }
  const int H = p.numRadii;
  for (int i = 0; i < H; ++i) radii.push_back(H == 1 ? r0 : r0 * std::pow(rh / r0, double(i) / double(H - 1)));
  return radii;
}

FitmapResult ComputeFitmaps(const TriData& input, const EmbreeScene& scene, const FitmapParams& p,
                            vcg::CallBackPos* cb) {
  const auto t0 = std::chrono::steady_clock::now();
  FitmapResult res;
  res.error = CheckFitmapInputs(input, scene, p);
  if (!res.error.empty()) return res;
  if (p.workingFaces > 0 && int(input.F.size()) > p.workingFaces && p.vertices.empty() &&
      p.mode == FitmapParams::Mode::Fast && !p.keepPerRadius) {
    return FitmapsFromWorkingResolution(input, p, cb);
  }

  // ---- vertices in Morton order (MortonOrder)
  const int nV = int(input.V.size());
  std::vector<int> order, rank;
  const TriData m = MortonOrdered(input, order, rank);

  // ---- radii: r_0 = average edge length, r_h = maxRadiusPercent of the diagonal (FitmapRadii)
  Context ctx;
  ctx.m = &m;
  ctx.orig = &order;
  ctx.scene = &scene;
  ctx.p = &p;
  ctx.tau = p.tauPercent / 100.0;
  const double r0 = AverageEdgeLength(m);
  const double diag = BBoxDiagonal(m.V);
  if (!(r0 > 0) || !std::isfinite(r0)) { res.error = "all edges have zero length"; return res; }
  const double rh = std::max(r0, p.maxRadiusPercent / 100.0 * diag);
  ctx.radii = FitmapRadii(r0, rh, diag, p);
  const int H = int(ctx.radii.size());
  res.radii = ctx.radii;

  Progress prog(cb);
  prog(0, "Fitmaps: preparing", true);
  ctx.faceArea.resize(m.F.size());
  for (size_t f = 0; f < m.F.size(); ++f) {
    const auto& t = m.F[f];
    ctx.faceArea[f] = 0.5 * (m.V[t[1]] - m.V[t[0]]).cross(m.V[t[2]] - m.V[t[0]]).norm();
    ctx.totalArea += ctx.faceArea[f];
  }
  if (!(ctx.totalArea > 0)) { res.error = "all faces have zero area"; return res; }
  const Adjacency vv = VertexVertexAdjacency(m.F, nV);
  ctx.normals = RobustNormals(m, vv, rh, res.fallbackNormals);

  // ---- which vertices
  const std::vector<int> todo = VerticesToCompute(ctx, rank, vv, res);

  Level fine = MakeFineLevel(m, vv, ctx.totalArea);
  if (p.mode == FitmapParams::Mode::Reference) {
    res.noFit = ReferenceValues(ctx, fine, todo, res, prog);
  } else {
    FastPlan plan = PlanFastLevels(ctx, std::move(fine), r0, rh);
    res.levels = int(plan.levels.size());
    res.secondsLevels = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (int i = 0; i < H; ++i) res.radiusLevel.push_back(plan.levelOf[i]);
    prog(5, "Fitmaps: coarse levels", true);
    const auto coarse = CoarseValues(ctx, plan);
    res.noFit = FastValues(ctx, plan, coarse, todo, res, prog, t0);
  }
  ToCallerOrder(order, H, res);  // back to the caller's vertex order
  prog(100, "Fitmaps: done", true);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace vcgext
