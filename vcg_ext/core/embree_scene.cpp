#include "vcg_ext/core/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>

namespace vcgext {

// The boundary edges as an Embree user geometry (SegmentBounds: their boxes, rounded outwards).
struct BoundarySegments {
  const std::vector<Vec3>* V;
  const std::vector<std::pair<int, int>>* edges;
  double scale;  ///< EmbreeScene::scale_ (the boxes are in Embree's frame)
};

namespace {
void ErrorHandler(void* user, RTCError code, const char* str) {
  auto* msg = static_cast<std::string*>(user);
  if (msg && msg->empty()) *msg = "Embree error " + std::to_string(int(code)) + ": " + (str ? str : "");
}

struct ClosestQuery {
  const TriData* mesh;
  EmbreeScene::Hit* best;
  double bestD2;
  double slack;  ///< widens each triangle's box past the rounding of its computed closest point
  double scale;  ///< EmbreeScene::scale_: Embree's query point and radius are in its frame
};

bool PointQueryFunc(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClosestQuery*>(args->userPtr);
  const auto& f = q->mesh->F[args->primID];
  const Vec3 p = Vec3(args->query->x, args->query->y, args->query->z) / q->scale;  // exact: a power of two
  const Vec3 &a = q->mesh->V[f[0]], &b = q->mesh->V[f[1]], &t = q->mesh->V[f[2]];
  // Embree calls this for every triangle of a leaf whose box meets the query sphere. A triangle
  // whose own box (widened by the slack) is farther than the best distance so far cannot give a
  // closer point: skipped before its closest point is computed (same answers; the margin of
  // 1e-9 covers the rounding of both squared distances). Half the callbacks on dense meshes.
  if (q->bestD2 < std::numeric_limits<double>::infinity()) {
    const Vec3 lo = a.cwiseMin(b).cwiseMin(t).array() - q->slack, hi = a.cwiseMax(b).cwiseMax(t).array() + q->slack;
    if ((lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm() > q->bestD2 * (1 + 1e-9)) return false;
  }
  double u, v;
  Vec3 c = ClosestPointOnTriangle(p, a, b, t, &u, &v);
  double d2 = (c - p).squaredNorm();
  if (d2 < q->bestD2) {
    q->bestD2 = d2;
    q->best->valid = true;
    q->best->face = int(args->primID);
    q->best->u = u;
    q->best->v = v;
    q->best->point = c;
    q->best->t = std::sqrt(d2);
    args->query->radius = float(std::sqrt(d2) * q->scale);
    return true;  // the query radius shrank
  }
  return false;
}
void SegmentBounds(const RTCBoundsFunctionArguments* args) {
  const auto* s = static_cast<const BoundarySegments*>(args->geometryUserPtr);
  const auto& e = (*s->edges)[args->primID];
  const Vec3 lo = (*s->V)[size_t(e.first)].cwiseMin((*s->V)[size_t(e.second)]) * s->scale;
  const Vec3 hi = (*s->V)[size_t(e.first)].cwiseMax((*s->V)[size_t(e.second)]) * s->scale;
  const float inf = std::numeric_limits<float>::infinity();
  RTCBounds* b = args->bounds_o;
  b->lower_x = std::nextafter(float(lo[0]), -inf), b->upper_x = std::nextafter(float(hi[0]), inf);
  b->lower_y = std::nextafter(float(lo[1]), -inf), b->upper_y = std::nextafter(float(hi[1]), inf);
  b->lower_z = std::nextafter(float(lo[2]), -inf), b->upper_z = std::nextafter(float(hi[2]), inf);
}

struct SegmentQuery {
  const BoundarySegments* segments;
  Vec3 p;        // the query point (Embree's is float)
  double offset;  // |p - Embree's float point|: widens the query sphere
  EmbreeScene::Hit* best;
  double bestD2;
};

bool SegmentQueryFunc(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<SegmentQuery*>(args->userPtr);
  const auto& e = (*q->segments->edges)[args->primID];
  const Vec3 &a = (*q->segments->V)[size_t(e.first)], &b = (*q->segments->V)[size_t(e.second)];
  const Vec3& p = q->p;
  const Vec3 d = b - a;
  const double l2 = d.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  const Vec3 x = a + t * d;
  const double d2 = (x - p).squaredNorm();
  if (!(d2 < q->bestD2)) return false;
  q->bestD2 = d2;
  *q->best = EmbreeScene::Hit{true, std::sqrt(d2), int(args->primID), t, 0, x};
  // shrink the query sphere (around the float point), widened so that a segment as close to p
  // is still visited
  args->query->radius = float((std::sqrt(d2) + q->offset) * (1 + 1e-6) * q->segments->scale);
  return true;
}
}  // namespace

EmbreeScene::EmbreeScene(const TriData& m) : mesh_(m) {
  const double diag = BBoxDiagonal(mesh_.V);
  eps_ = 1e-7 * diag;
  coordScale_ = LargestCoordinate(mesh_.V);
  if (diag > 0 && std::isfinite(diag) && (diag < kMinUnscaledDiagonal || diag > kMaxUnscaledDiagonal))
    scale_ = std::ldexp(1.0, -std::ilogb(diag));
  device_ = rtcNewDevice("threads=0");
  if (!device_) { error_ = "Embree: cannot create a device"; return; }
  rtcSetDeviceErrorFunction(device_, ErrorHandler, &error_);
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                         RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                         mesh_.V.size()));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                            RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                            mesh_.F.size()));
  if (!vb || !ib) {
    rtcReleaseGeometry(geom);
    if (error_.empty()) error_ = "Embree: cannot allocate buffers";
    return;
  }
  for (size_t i = 0; i < mesh_.V.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = float(mesh_.V[i][k] * scale_);
  for (size_t i = 0; i < mesh_.F.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = unsigned(mesh_.F[i][k]);
  rtcSetGeometryPointQueryFunction(geom, PointQueryFunc);
  rtcCommitGeometry(geom);
  RTCScene scene = rtcNewScene(device_);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  if (!error_.empty()) { rtcReleaseScene(scene); return; }
  scene_ = scene;
  BuildBoundaryScene();
}

void EmbreeScene::BuildBoundaryScene() {
  boundary_ = BoundaryHalfEdges(mesh_);
  if (boundary_.empty()) return;
  segments_ = std::make_unique<BoundarySegments>(BoundarySegments{&mesh_.V, &boundary_, scale_});
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, unsigned(boundary_.size()));
  rtcSetGeometryUserData(geom, segments_.get());
  rtcSetGeometryBoundsFunction(geom, SegmentBounds, nullptr);
  rtcSetGeometryPointQueryFunction(geom, SegmentQueryFunc);
  rtcCommitGeometry(geom);
  RTCScene scene = rtcNewScene(device_);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  if (!error_.empty()) {
    rtcReleaseScene(scene);
    rtcReleaseScene(scene_);
    scene_ = nullptr;
    return;
  }
  boundaryScene_ = scene;
}

EmbreeScene::Hit EmbreeScene::ClosestBoundaryPoint(const Vec3& p) const {
  Hit best;
  if (!boundaryScene_ || !p.allFinite()) return best;
  RTCPointQuery query;
  query.x = float(p[0] * scale_);
  query.y = float(p[1] * scale_);
  query.z = float(p[2] * scale_);
  const double offset = (p - Vec3(query.x, query.y, query.z) / scale_).norm();
  SegmentQuery q{segments_.get(), p, offset, &best, std::numeric_limits<double>::infinity()};
  query.radius = std::numeric_limits<float>::infinity();
  query.time = 0.f;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(boundaryScene_, &query, &ctx, nullptr, &q);
  return best;
}

EmbreeScene::~EmbreeScene() {
  if (boundaryScene_) rtcReleaseScene(boundaryScene_);
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

EmbreeScene::Hit EmbreeScene::Intersect(const Vec3& org, const Vec3& dir, double tnear,
                                        double tfar) const {
  Hit h;
  // a ray Embree cannot represent (non-finite, or beyond its FLT_LARGE = 1.844e18: ray.valid())
  // hits nothing (the fuzzer found Fitmaps rays with overflowing directions on degenerate input,
  // and origins beyond 1.8e18 on huge meshes: Debian's Embree asserts on them)
  const auto representable = [](const Vec3& x) { return x.allFinite() && x.cwiseAbs().maxCoeff() < 1.8e18; };
  const Vec3 o = org * scale_;  // Embree's frame
  if (!scene_ || !representable(o) || !representable(dir) || std::isnan(tnear) || std::isnan(tfar)) return h;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = float(o[0]); rh.ray.org_y = float(o[1]); rh.ray.org_z = float(o[2]);
  rh.ray.dir_x = float(dir[0]); rh.ray.dir_y = float(dir[1]); rh.ray.dir_z = float(dir[2]);
  rh.ray.tnear = float(tnear * scale_);
  rh.ray.tfar = std::isfinite(tfar) ? float(tfar * scale_) : std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.flags = 0;
  rh.ray.time = 0.f;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.valid = true;
  h.t = rh.ray.tfar / scale_;
  h.face = int(rh.hit.primID);
  h.u = rh.hit.u;
  h.v = rh.hit.v;
  const auto& f = mesh_.F[h.face];
  h.point = (1 - h.u - h.v) * mesh_.V[f[0]] + h.u * mesh_.V[f[1]] + h.v * mesh_.V[f[2]];
  return h;
}

EmbreeScene::Hit EmbreeScene::IntersectLine(const Vec3& org, const Vec3& dir, double maxDist) const {
  Hit fwd = Intersect(org, dir, 0.0, maxDist);
  Hit bwd = Intersect(org, -dir, 0.0, fwd.valid ? fwd.t : maxDist);
  if (bwd.valid) { bwd.t = -bwd.t; return bwd; }
  return fwd;
}

EmbreeScene::Hit EmbreeScene::NearestOnLine(const Vec3& c, const Vec3& dir, double maxDist, double window,
                                            signed char* side) const {
  const double s = (side && *side < 0) ? -1.0 : 1.0;
  const Vec3 d = s * dir;  // the guessed side
  const double eps = eps_;
  // distance from c of a hit of a ray started a hair (eps) behind c
  auto fromC = [&](Hit h) { h.t -= eps; return h; };
  // the answer: h at distance `dist` from c on side sgn (of d); signed t along dir
  auto answer = [&](Hit h, double dist, double sgn) {
    h.t = s * sgn * dist;
    if (side && h.valid) *side = h.t < 0 ? -1 : 1;
    return h;
  };
  // nearer of a d-side hit (distance df) and a -d-side hit (db); equal: the +dir one. Distances
  // of rays started behind c can be slightly negative (a surface through c): compared by size.
  auto nearer = [&](const Hit& f, double df, const Hit& b, double db) {
    if (!f.valid) return answer(b, db, -1);
    if (!b.valid) return answer(f, df, 1);
    const double af = std::abs(df), ab = std::abs(db);
    if (af < ab || (af == ab && s > 0)) return answer(f, df, 1);
    return answer(b, db, -1);
  };
  const double T = std::min(std::max(window, 0.0), maxDist);
  if (T > 0) {
    Hit w = Intersect(c - T * d, d, 0.0, T + maxDist);
    if (w.valid) {
      const double s1 = w.t - T;  // offset of the first hit in [-T, maxDist] along d
      if (s1 >= 0 && s1 <= T) return answer(w, s1, 1);  // nothing on the -d side within T >= s1
      if (s1 > T) {  // -d side: only hits farther than T can beat it
        Hit b = fromC(Intersect(c + eps * d, -d, 0.0, s1 + 2 * eps));
        return nearer(w, s1, b, b.valid ? b.t : 0.0);
      }
      // a hit on the -d side within T: its nearest one, then the d side up to it
      Hit b = fromC(Intersect(c + eps * d, -d, 0.0, -s1 + 2 * eps));
      if (!b.valid) { b = w; b.t = -s1; }
      Hit f = fromC(Intersect(c - eps * d, d, 0.0, b.t + 2 * eps));
      return nearer(f, f.valid ? f.t : 0.0, b, b.t);
    }
    // nothing in [-T, maxDist] along d: the -d side beyond T decides
    Hit b = fromC(Intersect(c + eps * d, -d, 0.0, maxDist + eps));
    return answer(b, b.valid ? b.t : 0.0, -1);
  }
  // no window: the two rays of the plain query (the second one only needs to beat the first)
  Hit f = fromC(Intersect(c - eps * d, d, 0.0, maxDist + eps));
  Hit b = fromC(Intersect(c + eps * d, -d, 0.0, f.valid ? f.t + 3 * eps : maxDist + eps));
  return nearer(f, f.valid ? f.t : 0.0, b, b.valid ? b.t : 0.0);
}

EmbreeScene::Hit EmbreeScene::ClosestPoint(const Vec3& p, double maxDist, int hintFace) const {
  Hit best;
  if (!scene_ || !p.allFinite() || (p * scale_).cwiseAbs().maxCoeff() >= 1.8e18 || std::isnan(maxDist)) return best;
  ClosestQuery q{&mesh_, &best, std::numeric_limits<double>::infinity(), 1e-10 * coordScale_, scale_};
  RTCPointQuery query;
  query.x = float(p[0] * scale_); query.y = float(p[1] * scale_); query.z = float(p[2] * scale_);
  query.radius = std::isfinite(maxDist) ? float(maxDist * scale_) : std::numeric_limits<float>::infinity();
  if (hintFace >= 0 && hintFace < int(mesh_.F.size())) {
    // an upper bound of the answer's distance, widened past float rounding: Embree's tree and
    // query point are floats (a relative 1.2e-7 of the coordinates), the callback's distances doubles
    const auto& f = mesh_.F[hintFace];
    const double d = (ClosestPointOnTriangle(p, mesh_.V[f[0]], mesh_.V[f[1]], mesh_.V[f[2]]) - p).norm();
    const double bound = d * 1.001 + 10 * eps_ + 1e-6 * (p.cwiseAbs().maxCoeff() + coordScale_);
    if (bound * scale_ < query.radius) query.radius = float(bound * scale_);
  }
  query.time = 0.f;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(scene_, &query, &ctx, nullptr, &q);
  return best;
}

Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double* u,
                            double* v) {
  // Ericson, Real-Time Collision Detection, §5.1.5 (Voronoi regions).
  auto out = [&](double bu, double bv) {
    if (u) *u = bu;
    if (v) *v = bv;
    return Vec3(a + bu * (b - a) + bv * (c - a));
  };
  Vec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return out(0, 0);
  Vec3 bp = p - b;
  double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return out(1, 0);
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return out(d1 / (d1 - d3), 0);
  Vec3 cp = p - c;
  double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return out(0, 1);
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return out(0, d2 / (d2 - d6));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return out(1 - w, w);
  }
  double denom = 1.0 / (va + vb + vc);
  return out(vb * denom, vc * denom);
}

}  // namespace vcgext
