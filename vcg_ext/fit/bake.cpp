/// \file bake.cpp
/// The displacement bake (paper §4, BakeDisplacement) and the one-call pipeline FitAndBake:
/// fit, tessellate, bake, texel fit, metrics, timings. The pieces: tessellate.cpp, atlas_layout.cpp,
/// texel_space.cpp, texel_fit.cpp, renderer_grid.cpp, metrics.cpp, bake_report.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "vcg_ext/fit/bake.h"
#include "vcg_ext/core/memory.h"
#include "vcg_ext/core/progress.h"
#include "vcg_ext/core/stopwatch.h"
#include "vcg_ext/fit/fit_internal.h"
#include "vcg_ext/fit/renderer_grid.h"
#include "vcg_ext/fit/texel_space.h"

namespace vcgext {

using namespace fitdetail;

DisplacementAtlas BakeDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                   const EmbreeScene& scene, int R, double maxDist, bool normalMap) {
  DisplacementAtlas a;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || R < 2) return a;
  UniformAtlasLayout(a, nF, R);
  BakeDisplacement(ls, ctrl, ref, scene, maxDist, normalMap, a);
  return a;
}

namespace {

// What every texel of the bake reads: the surface, the reference with its face normals (and vertex
// normals for the normal map), the renderer's grid (rendererLevel > 0) and the projection reach.
struct TexelBake {
  const LimitSurface& ls;
  const std::vector<Vec3>& ctrl;
  const TriData& ref;
  const EmbreeScene& scene;
  const std::vector<Vec3>& refN;
  const std::vector<Vec3>& vn;  ///< empty without the normal map
  const LimitTessellation& grid;
  double maxDist;
  bool normalMap;
};

// Bakes texel (i, j) of patch f into `a` (the displacement along the normal, the normal map's
// colour); false when the normal line missed the reference (the closest point stands in).
bool BakeTexel(const TexelBake& b, int f, int i, int j, DisplacementAtlas& a) {
  const int R = a.tileR[f];
  Vec3 n, P;
  if (a.rendererLevel > 0) {
    const int s = b.grid.N / (R - 1), g = GridVertex(b.grid, f, i * s, j * s);
    P = b.grid.mesh.V[g];
    n = b.grid.normal[g];
  } else {
    P = fitdetail::LimitPointNormal(b.ls, b.ctrl, f, double(i) / (R - 1), double(j) / (R - 1), &n);
  }
  double d = 0;
  EmbreeScene::Hit h;
  if (n.squaredNorm() > 0) h = fitdetail::IntersectLineOriented(b.scene, b.refN, P, n, b.maxDist);
  const bool missed = !h.valid;
  if (h.valid) {
    d = h.t;
  } else {
    h = b.scene.ClosestPoint(P, b.maxDist);
    if (h.valid) d = (h.point - P).dot(n);
  }
  const size_t px = a.Pixel(f, i, j);
  a.disp[px] = float(d);
  if (b.normalMap) {
    Vec3 nn = n;
    if (h.valid) {
      const auto& t = b.ref.F[h.face];
      nn = (1 - h.u - h.v) * b.vn[t[0]] + h.u * b.vn[t[1]] + h.v * b.vn[t[2]];
      if (nn.norm() > 0) nn.normalize();
    }
    for (int c = 0; c < 3; ++c)
      a.normalRGB[px * 3 + c] = std::uint8_t(std::clamp(std::lround((nn[c] + 1) * 0.5 * 255), 0L, 255L));
  }
  return missed;
}

// Wedge UVs at the corner texels' centres; v up (OpenGL / OBJ / MeshLab), image row 0 on top.
void SetWedgeUVs(DisplacementAtlas& a, int nF) {
  a.wedgeUV.resize(nF);
  const int cu[4] = {0, 1, 1, 0}, cvv[4] = {0, 0, 1, 1};
  for (int f = 0; f < nF; ++f) {
    const int R = a.tileR[f];
    for (int c = 0; c < 4; ++c) {
      double x = a.tileX[f] + 0.5 + cu[c] * (R - 1), y = a.tileY[f] + 0.5 + cvv[c] * (R - 1);
      a.wedgeUV[f][c] = Eigen::Vector2d(x / a.width, 1.0 - y / a.height);
    }
  }
}

}  // namespace

void BakeDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                      const EmbreeScene& scene, double maxDist, bool normalMap, DisplacementAtlas& a) {
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || !LayoutOk(a, nF)) {
    a = DisplacementAtlas();
    return;
  }
  a.disp.assign(size_t(a.width) * a.height, 0.f);
  a.normalRGB.clear();
  if (normalMap) a.normalRGB.assign(size_t(a.width) * a.height * 3, 128);
  std::vector<Vec3> vn;
  if (normalMap) vn = VertexNormals(ref);
  const std::vector<Vec3> refN = FaceNormals(ref);
  // Renderer grid (issue 15): each texel sits on a vertex of the level-L grid and takes its normal.
  if (a.rendererLevel > 0 && RendererLevel(a) < a.rendererLevel) a.rendererLevel = 0;
  const LimitTessellation grid =
      a.rendererLevel > 0 ? RendererGrid(ls, ctrl, a.rendererLevel) : LimitTessellation();
  if (a.rendererLevel > 0 && grid.N == 0) a.rendererLevel = 0;
  const TexelBake bake{ls, ctrl, ref, scene, refN, vn, grid, maxDist, normalMap};
  int misses = 0;
#pragma omp parallel for schedule(dynamic, 8) reduction(+ : misses)
  for (int f = 0; f < nF; ++f) {
    const int R = a.tileR[f];
    for (int j = 0; j < R; ++j)
      for (int i = 0; i < R; ++i) misses += BakeTexel(bake, f, i, j, a) ? 1 : 0;
  }
  a.misses = misses;
  // One value per surface point: shared texels agree, finer edges follow coarser neighbours.
  const TexelSpace space(ls, a);
  space.Scatter(space.Gather(a), a);
  Quantize(a);
  SetWedgeUVs(a, nF);
}

namespace {

// r.atlas's tiles for the limit's `patches` (the paper's budget, one texel per reference vertex up
// to FitBakeParams::maxTexels; uniform or adaptive tiles), with the renderer's grid level.
void LayOutAtlas(int patches, const TriData& ref, const FitBakeParams& p, FitBakeResult& r) {
  const int budgetVertices = p.maxTexels > 0 ? std::min(r.referenceVertices, p.maxTexels) : r.referenceVertices;
  if (p.textureResolution > 0 || !p.adaptiveTiles)
    UniformAtlasLayout(r.atlas, patches,
                       p.textureResolution > 0 ? p.textureResolution : AutoTextureResolution(budgetVertices, patches));
  else
    AdaptiveAtlasLayout(r.atlas, AdaptiveTileResolutions(PatchAreas(r.limit, patches),
                                                         PatchVertexCounts(r.limit, patches, ref),
                                                         AutoTextureBudget(budgetVertices, patches)));
  if (p.rendererGrid) {
    r.atlas.rendererLevel = RendererLevel(r.atlas);
    if (r.atlas.rendererLevel == 0)
      r.warnings.push_back("the renderer's grid needs tiles of 2^k+1 texels (automatic tile sizes); the "
                           "displacement was baked for the per-tile surface along the limit normal");
  }
}

// r.metrics: the limit (on its metric tessellation, AutoMetricSegments) and the displaced surface
// against the reference (`scene` is the reference's), in per mille of its diagonal `diag`;
// unprojectable beyond `maxDist`.
void MeasureResult(const LimitSurface& ls, const TriData& ref, const EmbreeScene& scene, const FitBakeParams& p,
                   double diag, double maxDist, FitBakeResult& r) {
  int Nm = p.metricSegments;
  if (Nm == 0)
    Nm = AutoMetricSegments(long(ref.F.size()), ls.NumFaces(), p.limitSegments);
  LimitTessellation dense = Nm == p.limitSegments ? r.limit : TessellateLimit(ls, r.fit.control.V, Nm);
  const EmbreeScene denseScene(dense.mesh);  // one scene for the limit error and projectability
  auto el = ReferenceToSurfaceError(ref, denseScene);
  const EmbreeScene displacedScene(r.displaced.mesh);  // one scene for both displaced checks
  auto ed = ReferenceToSurfaceError(ref, displacedScene);
  const double pm = diag > 0 ? 1000.0 / diag : 0.0;
  r.metrics.rmsLimitPermille = el.first * pm;
  r.metrics.maxLimitPermille = el.second * pm;
  r.metrics.rmsDisplacedPermille = ed.first * pm;
  r.metrics.maxDisplacedPermille = ed.second * pm;
  double mx = 0;
  for (double q : r.limit.quality) mx = std::max(mx, std::abs(q));
  r.metrics.maxLimitToRefPermille = mx * pm;
  r.metrics.rmsDisplacedAreaPermille = AreaSampledDistance(ref, displacedScene).first * pm;
  const auto dr = AreaSampledDistance(r.displaced.mesh, scene, true);
  r.metrics.rmsDisplacedToRefPermille = dr.first * pm;
  r.metrics.maxDisplacedToRefPermille = dr.second * pm;
  r.metrics.displacedFolds = FoldedTriangles(r.displaced);
  r.metrics.limitFolds = FoldedTriangles(dense);
  r.metrics.unprojectablePct = UnprojectablePercent(dense, denseScene, ref, scene, maxDist);
}

}  // namespace

FitBakeResult FitAndBake(const QuadData& control, const TriData& ref, const EmbreeScene& scene, const FitBakeParams& p,
                         vcg::CallBackPos* cb) {
  FitBakeResult r;
  const auto t0 = Clock::now();
  Progress prog(cb);
  r.referenceVertices = int(ref.V.size());
  r.referenceFaces = int(ref.F.size());
  if (p.limitSegments < 1 || p.textureResolution < 0 || p.textureResolution == 1 || p.maxDistPercent <= 0 ||
      p.metricSegments < 0 || p.maxTexels < 0) {
    r.error = "invalid parameters (limit segments >= 1, texture resolution 0 (auto) or >= 2, positive distance)";
    return r;
  }
  r.fit = FitCatmullClark(control, ref, scene, p.fit, nullptr);
  if (!r.fit.error.empty()) { r.error = r.fit.error; return r; }
  r.times.emplace_back("fit", r.fit.seconds);
  r.memory.emplace_back("fit", StagePeakMemoryMb());
  prog(50, "Fit and bake: tessellating", true);
  const double diag = BBoxDiagonal(ref.V);
  const double maxDist = p.maxDistPercent / 100.0 * diag;
  auto t = Clock::now();
  LimitSurface ls = LimitSurface::FromQuads(r.fit.control);
  if (!ls.Ok()) { r.error = ls.Error(); return r; }
  const auto& ctrl = r.fit.control.V;
  r.limit = TessellateLimit(ls, ctrl, p.limitSegments);
  r.limit.quality = SignedDistanceToReference(r.limit.mesh.V, scene, std::numeric_limits<double>::infinity());
  r.times.emplace_back("tessellate", Since(t));
  r.memory.emplace_back("tessellate", StagePeakMemoryMb());
  prog(60, "Fit and bake: baking displacement", true);
  t = Clock::now();
  LayOutAtlas(ls.NumFaces(), ref, p, r);
  BakeDisplacement(ls, ctrl, ref, scene, maxDist, p.normalMap, r.atlas);
  // one base for the texel fit and the displaced layer (BakeDisplacement still builds its own grid)
  LimitTessellation base = DisplacementBase(ls, ctrl, r.atlas, p.limitSegments);
  if (p.fitDisplacement) r.displacementFit = FitDisplacement(ls, ref, base, maxDist, p.displacementFit, r.atlas);
  r.displaced = DisplacedSurface(ls, r.atlas, std::move(base));
  r.displaced.quality = SignedDistanceToReference(r.displaced.mesh.V, scene, std::numeric_limits<double>::infinity());
  r.times.emplace_back("bake", Since(t));
  r.memory.emplace_back("bake", StagePeakMemoryMb());
  if (p.computeMetrics) {
    prog(75, "Fit and bake: measuring", true);
    t = Clock::now();
    MeasureResult(ls, ref, scene, p, diag, maxDist, r);
    r.times.emplace_back("metrics", Since(t));
    r.memory.emplace_back("metrics", StagePeakMemoryMb());
  }
  r.totalSeconds = Since(t0);
  // Set-up between the timed stages (limit surface, scenes): its own entry, so that the stages
  // add up to the total exactly (the report promises that).
  double staged = 0;
  for (const auto& st : r.times) staged += st.second;
  r.times.emplace_back("fit_setup", std::max(0.0, r.totalSeconds - staged));
  r.totalSeconds = staged + r.times.back().second;
  r.peakMemoryMb = ProcessPeakMemoryMb();
  for (auto& w : ResultWarnings(r)) r.warnings.push_back(std::move(w));
  prog(100, "Fit and bake: done", true);
  return r;
}

}  // namespace vcgext
