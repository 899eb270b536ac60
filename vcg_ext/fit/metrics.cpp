/// \file metrics.cpp
/// The Table-1 measurements of bake.h: distances between the reference and a surface (per vertex,
/// area-sampled), folds, projectability.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/fit_internal.h"

namespace vcgext {

std::vector<double> SignedDistanceToReference(const std::vector<Vec3>& pts, const EmbreeScene& ref, double maxDist) {
  std::vector<double> d(pts.size(), maxDist);
  const auto fn = FaceNormals(ref.Mesh());
#pragma omp parallel
  {
    int hint = -1;  // the previous point's face (ClosestPoint's hint: neighbouring points)
#pragma omp for schedule(static)
    for (long i = 0; i < long(pts.size()); ++i) {
      EmbreeScene::Hit h = ref.ClosestPoint(pts[i], maxDist, hint);
      if (!h.valid) continue;
      hint = h.face;
      Vec3 dv = pts[i] - h.point;
      double s = dv.dot(fn[h.face]) < 0 ? -1.0 : 1.0;
      d[i] = s * dv.norm();
    }
  }
  return d;
}

int FoldedTriangles(const LimitTessellation& t) {
  int n = 0;
  for (const auto& f : t.mesh.F) {
    const Vec3 fn = (t.mesh.V[f[1]] - t.mesh.V[f[0]]).cross(t.mesh.V[f[2]] - t.mesh.V[f[0]]);
    if (fn.dot(t.normal[f[0]] + t.normal[f[1]] + t.normal[f[2]]) < 0) ++n;
  }
  return n;
}

std::pair<double, double> ReferenceToSurfaceError(const TriData& ref, const TriData& surf) {
  return ReferenceToSurfaceError(ref, EmbreeScene(surf));
}
std::pair<double, double> ReferenceToSurfaceError(const TriData& ref, const EmbreeScene& s) {
  if (!s.Ok() || ref.V.empty()) return {0.0, 0.0};
  double sum = 0, mx = 0;
#pragma omp parallel reduction(+ : sum) reduction(max : mx)
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long i = 0; i < long(ref.V.size()); ++i) {
      EmbreeScene::Hit h = s.ClosestPoint(ref.V[i], std::numeric_limits<double>::infinity(), hint);
      if (h.valid) hint = h.face;
      double d = h.valid ? (h.point - ref.V[i]).norm() : 0.0;
      sum += d * d;
      mx = std::max(mx, d);
    }
  }
  return {std::sqrt(sum / ref.V.size()), mx};
}

std::pair<double, double> AreaSampledDistance(const TriData& from, const TriData& to, bool threePoint) {
  return AreaSampledDistance(from, EmbreeScene(to), threePoint);
}
std::pair<double, double> AreaSampledDistance(const TriData& from, const EmbreeScene& s, bool threePoint) {
  if (!s.Ok() || from.F.empty()) return {0.0, 0.0};
  double sw = 0, sd = 0, mx = 0;
#pragma omp parallel reduction(+ : sw, sd) reduction(max : mx)
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long t = 0; t < long(from.F.size()); ++t) {
      const auto& f = from.F[t];
      const Vec3 &a = from.V[f[0]], &b = from.V[f[1]], &c = from.V[f[2]];
      const double w = 0.5 * (b - a).cross(c - a).norm() / (threePoint ? 3 : 1);
      for (int k = 0; k < (threePoint ? 3 : 1); ++k) {
        const Vec3 q = threePoint ? Vec3((a + b + c + 3.0 * (k == 0 ? a : k == 1 ? b : c)) / 6.0) : Vec3((a + b + c) / 3.0);
        const EmbreeScene::Hit h = s.ClosestPoint(q, std::numeric_limits<double>::infinity(), hint);
        if (h.valid) hint = h.face;
        const double d = h.valid ? (h.point - q).norm() : 0.0;
        sw += w;
        sd += w * d * d;
        mx = std::max(mx, d);
      }
    }
  }
  return {sw > 0 ? std::sqrt(sd / sw) : 0.0, mx};
}

double UnprojectablePercent(const LimitTessellation& lim, const TriData& ref, const EmbreeScene& scene, double maxDist) {
  return UnprojectablePercent(lim, EmbreeScene(lim.mesh), ref, scene, maxDist);
}
double UnprojectablePercent(const LimitTessellation& lim, const EmbreeScene& ls, const TriData& ref,
                            const EmbreeScene& scene, double maxDist) {
  const int nT = int(ref.F.size());
  if (nT == 0) return 0.0;
  std::vector<unsigned char> reached(nT, 0);
#pragma omp parallel for schedule(static)
  for (long v = 0; v < long(lim.mesh.V.size()); ++v) {
    if (lim.normal[v].squaredNorm() == 0) continue;
    EmbreeScene::Hit h = scene.IntersectLine(lim.mesh.V[v], lim.normal[v], maxDist);
    if (h.valid) {
#pragma omp atomic write
      reached[h.face] = 1;
    }
  }
  double total = 0, missed = 0;
#pragma omp parallel reduction(+ : total, missed)
  {
    int hint = -1;
#pragma omp for schedule(dynamic, 64)
    for (int t = 0; t < nT; ++t) {
      const auto& f = ref.F[t];
      const Vec3 &a = ref.V[f[0]], &b = ref.V[f[1]], &c = ref.V[f[2]];
      const double area = 0.5 * (b - a).cross(c - a).norm();
      total += area;
      unsigned char r;
#pragma omp atomic read
      r = reached[t];
      if (r) continue;
      bool ok = false;
      EmbreeScene::Hit q = ls.ClosestPoint((a + b + c) / 3.0, maxDist, hint);
      if (q.valid) {
        hint = q.face;
        const auto& g = lim.mesh.F[q.face];
        Vec3 n = (1 - q.u - q.v) * lim.normal[g[0]] + q.u * lim.normal[g[1]] + q.v * lim.normal[g[2]];
        if (n.norm() > 0) {
          EmbreeScene::Hit h = scene.IntersectLine(q.point, n.normalized(), maxDist);
          ok = h.valid && h.face == t;
        }
      }
      if (!ok) missed += area;
    }
  }
  return total > 0 ? 100.0 * missed / total : 0.0;
}

}  // namespace vcgext
