// Tests of the Loop surface kernel against an independent reference (OpenSubdiv via
// vcgext::LimitSurface), finite differences, limit masks and the 1-D crease spline.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "test_support.h"
#include "vcg_ext/loop/loop_surface.h"
#include "vcg_ext/subdiv/limit_surface.h"

using vcgext::LoopEval;
using vcgext::LoopSurface;
using vcgext::LoopSurfaceParams;
using vcgext::TriData;
using vcgext::Vec3;

namespace {

/// OpenSubdiv reference with the same hard edges (interior ones as infinitely sharp creases;
/// boundaries are sharp by Sdc's EDGE_ONLY rule) and its finest approximation level (10).
vcgext::LimitSurface Reference(const LoopSurface& s) {
  vcgext::LimitSurfaceOptions o;
  for (int f = 0; f < s.NumFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      int g = s.FaceAcross(f, k);
      if (s.EdgeHard(f, k) && g >= 0 && f < g) o.creaseEdges.push_back({s.Net().F[f][k], s.Net().F[f][(k + 1) % 3]});
    }
  o.approxLevelSmooth = 10;
  o.approxLevelSharp = 10;
  return vcgext::LimitSurface::FromTriangles(s.Net(), o);
}

/// Whether a corner of face f is irregular for OpenSubdiv's patches (its end caps are
/// approximations within 2^-10 of such a corner).
bool NearIrregular(const LoopSurface& s, const vcgext::LimitSurface& ref, int f, double v, double w, double r) {
  (void)ref;
  if (s.FaceIsRegular(f)) return false;
  double b[3] = {1 - v - w, v, w};
  for (int k = 0; k < 3; ++k)
    if (1.0 - b[k] < r) return true;
  return false;
}

struct Agreement {
  double maxFar = 0, maxNear = 0, maxDer = 0;
  int nFar = 0, nNear = 0;
};

Agreement Compare(const LoopSurface& s, int n, unsigned seed) {
  auto ref = Reference(s);
  EXPECT_TRUE(ref.Ok()) << ref.Error();
  Agreement a;
  if (!ref.Ok()) return a;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  double diag = vcgext::BBoxDiagonal(s.Net().V);
  for (int i = 0; i < n; ++i) {
    int f = int(rng() % s.NumFaces());
    double v = U(rng), w = U(rng);
    if (v + w > 1) { v = 1 - v; w = 1 - w; }
    LoopEval e;
    EXPECT_TRUE(s.Evaluate(f, v, w, e, 1));
    Vec3 P, Du, Dv;
    ref.Evaluate(f, v, w, s.Net().V, &P, &Du, &Dv);
    double d = (P - e.P).norm() / diag;
    if (NearIrregular(s, ref, f, v, w, 1.0 / 32)) { a.maxNear = std::max(a.maxNear, d); ++a.nNear; }
    else {
      a.maxFar = std::max(a.maxFar, d);
      ++a.nFar;
      double scale = std::max(1e-12, Du.norm() + Dv.norm());
      a.maxDer = std::max(a.maxDer, ((Du - e.Dv).norm() + (Dv - e.Dw).norm()) / scale);
    }
  }
  return a;
}

}  // namespace

TEST(LoopSurface, RegularGridIsBoxSplineOfPlane) {
  // A plane stays a plane and the parameterisation is linear in the interior of a regular grid.
  TriData m = testsupport::PlaneGrid(8, 8, 1.0);
  LoopSurface s(m);
  ASSERT_TRUE(s.Ok()) << s.Error();
  for (int f = 0; f < s.NumFaces(); ++f) {
    LoopEval e;
    s.Evaluate(f, 0.3, 0.2, e);
    EXPECT_NEAR(e.P.z(), 0.0, 1e-14);
    // box-spline (incl. ghost-completed boundary) patches reproduce linear functions
    if (s.FaceIsRegular(f)) { EXPECT_NEAR(e.Dvv.norm() + e.Dww.norm() + e.Dvw.norm(), 0.0, 1e-10); }
  }
}

TEST(LoopSurface, AgreesWithOpenSubdivSmooth) {
  for (const char* name : {"elephant.off", "bunny00.off"}) {
    TriData m = testsupport::LoadSample(name);
    LoopSurfaceParams p;
    p.creaseAngleDeg = 0;  // no creases: smooth Loop everywhere
    LoopSurface s(m, p);
    ASSERT_TRUE(s.Ok()) << s.Error();
    Agreement a = Compare(s, 12000, 7);
    // Exact kernels on both sides away from irregular corners: rounding only.
    EXPECT_LT(a.maxFar, 1e-10) << name;
    EXPECT_LT(a.maxDer, 1e-8) << name;
    // Within 1/32 of an irregular corner OpenSubdiv uses Gregory end caps below level 10.
    EXPECT_LT(a.maxNear, 1e-5) << name;
    std::printf("[%s smooth] far %d pts max %.2e (deriv %.2e); near %d pts max %.2e; irregular faces %d\n", name,
                a.nFar, a.maxFar, a.maxDer, a.nNear, a.maxNear, s.NumIrregularFaces());
  }
}

TEST(LoopSurface, AgreesWithOpenSubdivCreases) {
  TriData m = testsupport::LoadSample("fandisk.off");
  LoopSurface s(m);  // 40 degree crease angle
  ASSERT_TRUE(s.Ok()) << s.Error();
  EXPECT_GT(s.NumHardEdges(), 100);
  Agreement a = Compare(s, 12000, 11);
  EXPECT_LT(a.maxFar, 1e-10);
  EXPECT_LT(a.maxDer, 1e-8);
  EXPECT_LT(a.maxNear, 1e-5);
  std::printf("[fandisk creases] hard edges %d corners %d; far %d pts max %.2e (deriv %.2e); near %d pts max %.2e\n",
              s.NumHardEdges(), s.NumCornerVertices(), a.nFar, a.maxFar, a.maxDer, a.nNear, a.maxNear);
}

TEST(LoopSurface, AgreesWithOpenSubdivBoundary) {
  TriData m = testsupport::HeightField(9, 7, 1.0, [](double x, double y) { return 0.3 * std::sin(3 * x) * std::cos(2 * y); });
  // perturb to make it irregular: flip a few diagonals is hard with PlaneGrid; use valence via a fan
  LoopSurfaceParams p;
  p.creaseAngleDeg = 0;
  LoopSurface s(m, p);
  ASSERT_TRUE(s.Ok()) << s.Error();
  Agreement a = Compare(s, 10000, 3);
  EXPECT_LT(a.maxFar, 1e-10);
  EXPECT_LT(a.maxDer, 1e-8);
  EXPECT_LT(a.maxNear, 1e-5);
  std::printf("[height field boundary] far %d max %.2e; near %d max %.2e\n", a.nFar, a.maxFar, a.nNear, a.maxNear);
}

TEST(LoopSurface, DeepEvaluationPathsAgree) {
  // Points close to the corners (depth 3..27): cacheDepth 0 subdivides every level on the fly
  // (generic path), 2 uses cached tiles then the shared self-similar level matrices, 6 caches
  // deeper. The three must agree (and derivatives too).
  TriData m = testsupport::LoadSample("fandisk.off");
  LoopSurfaceParams p0, p2, p6;
  p0.cacheDepth = 0;
  p2.cacheDepth = 2;
  p6.cacheDepth = 6;
  LoopSurface s0(m, p0), s2(m, p2), s6(m, p6);
  ASSERT_TRUE(s0.Ok() && s2.Ok() && s6.Ok());
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(0, 1);
  const double diag = vcgext::BBoxDiagonal(m.V);
  double worstP = 0, worstD = 0;
  int deep = 0;
  for (int i = 0; i < 4000; ++i) {
    int f = int(rng() % s0.NumFaces());
    if (s0.FaceIsRegular(f)) continue;
    double r = std::pow(10.0, -1 - 7 * U(rng)), a = U(rng);
    double b[3];
    int k = int(rng() % 3);
    b[k] = 1 - r;
    b[(k + 1) % 3] = r * a;
    b[(k + 2) % 3] = r * (1 - a);
    LoopEval e0, e2, e6;
    s0.Evaluate(f, b[1], b[2], e0, 2);
    s2.Evaluate(f, b[1], b[2], e2, 2);
    s6.Evaluate(f, b[1], b[2], e6, 2);
    deep += e2.depth > 2;
    worstP = std::max({worstP, (e0.P - e2.P).norm() / diag, (e0.P - e6.P).norm() / diag});
    double sc = e0.Dv.norm() + e0.Dw.norm();
    // below depth ~16 the derivatives (scaled by 2^depth, tile differences shrinking like
    // lambda^depth) amplify round-off: 5e-8 at depth 17, up to 3e-5 at depth 24 (both paths exact
    // in exact arithmetic); compare them where they are meaningful
    if (e2.depth > 16) continue;
    worstD = std::max({worstD, ((e0.Dv - e2.Dv).norm() + (e0.Dw - e2.Dw).norm()) / sc,
                       ((e0.Dv - e6.Dv).norm() + (e0.Dw - e6.Dw).norm()) / sc});
  }
  EXPECT_GT(deep, 300);
  EXPECT_LT(worstP, 1e-13);
  EXPECT_LT(worstD, 1e-7);  // measured 3e-9 (depth 16)
  std::printf("[deep paths] %d deep points: position %.2e, first derivatives %.2e\n", deep, worstP, worstD);
}


// The surface's memory (EstimateLoopSurfaceMemoryMb) sets its cache depth: under a budget between
// the estimates for depth 0 and 1 it caches no level; under one below depth 0's it refuses with an
// error that names the cure. The estimate was fitted to the growth of the peak resident memory
// while the surface is built (loop_surface.cpp: the data set's scans within -14 ... +14 %), which a
// test cannot measure reliably (freed pages reused, transparent huge pages, the sanitizers'
// allocator); it is checked against the surface's own count of its cached patches (CacheBytes:
// measured, the resident memory is 1.4-2.0 times that at depth 2). Its count of irregular triangles
// (corners not all smooth, interior, of valence 6 without a hard edge, counted here from the
// surface's own queries) bounds the surface's.
TEST(LoopSurface, CacheDepthFollowsTheMemoryBudget) {
  const TriData m = testsupport::LoadSample("elephant.off");
  const LoopSurface full(m);
  ASSERT_TRUE(full.Ok()) << full.Error();
  EXPECT_EQ(full.CacheDepth(), 2);
  std::vector<int> faces(m.V.size(), 0);
  std::vector<char> hard(m.V.size(), 0);
  for (int f = 0; f < full.NumFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      ++faces[m.F[f][k]];
      if (full.EdgeHard(f, k)) hard[m.F[f][k]] = hard[m.F[f][(k + 1) % 3]] = 1;
    }
  long regular = 0;
  for (const auto& t : m.F) {
    bool r = true;
    for (int k = 0; k < 3; ++k)
      r = r && full.VertexType(t[k]) == vcgext::LoopVertexType::Smooth && !hard[t[k]] && faces[t[k]] == 6;
    regular += r ? 1 : 0;
  }
  const long irregular = long(m.F.size()) - regular;
  EXPECT_GE(irregular, full.NumIrregularFaces());
  const double e0 = vcgext::EstimateLoopSurfaceMemoryMb(irregular, regular, 0),
               e1 = vcgext::EstimateLoopSurfaceMemoryMb(irregular, regular, 1),
               e2 = vcgext::EstimateLoopSurfaceMemoryMb(irregular, regular, 2);
  const double cached = full.CacheBytes() / (1024.0 * 1024.0);
  std::printf("elephant's surface: cached patches %.1f MB, estimate %.1f MB (depth 0: %.1f)\n", cached, e2, e0);
  EXPECT_GE(e2, cached);
  EXPECT_LE(e2, 2.5 * cached);
  EXPECT_LT(e0, e1);
  LoopSurfaceParams p;
  p.maxMemoryMb = 0.5 * (e0 + e1);
  const LoopSurface low(m, p);
  ASSERT_TRUE(low.Ok()) << low.Error();
  EXPECT_EQ(low.CacheDepth(), 0);
  EXPECT_LT(low.CacheBytes(), full.CacheBytes() / 4);
  EXPECT_EQ(low.NumIrregularFaces(), full.NumIrregularFaces());
  p.maxMemoryMb = 0.9 * e0;
  const LoopSurface refused(m, p);
  EXPECT_FALSE(refused.Ok());
  EXPECT_NE(refused.Error().find("the Loop surface of 5558 triangles"), std::string::npos) << refused.Error();
  EXPECT_NE(refused.Error().find("would need about"), std::string::npos) << refused.Error();
  EXPECT_NE(refused.Error().find("decimate the mesh first"), std::string::npos) << refused.Error();
}

// Vertices of valence > 96 are evaluated by subdividing their whole ring at every level (no
// precomputed level matrix); issue 16's poles of valence 500 made that quadratic per level. The
// results must still be OpenSubdiv's, and the valence limits must give their clear errors.
TEST(LoopSurface, HighValencePolesAgreeWithOpenSubdivAndLimitsHold) {
  const TriData sphere = testsupport::UvSphere(200, 6);
  {
    LoopSurfaceParams low;
    low.maxValence = 199;
    LoopSurface refused(sphere, low);
    ASSERT_FALSE(refused.Ok());
    EXPECT_NE(refused.Error().find("200 triangles"), std::string::npos) << refused.Error();
    EXPECT_NE(refused.Error().find("remesh"), std::string::npos) << refused.Error();
  }
  LoopSurfaceParams p;
  p.creaseAngleDeg = 0;
  LoopSurface s(sphere, p);  // the default limit (2048) accepts it
  ASSERT_TRUE(s.Ok()) << s.Error();
  const Agreement a = Compare(s, 4000, 11);
  EXPECT_LT(a.maxFar, 1e-10);
  EXPECT_LT(a.maxDer, 1e-8);
  // Points close to the poles (faces 0..199 have the north pole as corner 0): deep evaluations
  // through the whole-ring subdivision, against OpenSubdiv. Down to 2^-7 of the corner both are
  // exact (measured: 1e-14); closer, OpenSubdiv's end-cap approximation at valence 200 is off by a
  // constant 4e-4, so there the pole's limit mask below is the reference.
  auto ref = Reference(s);
  ASSERT_TRUE(ref.Ok()) << ref.Error();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  double maxNear = 0;
  int deep = 0;
  for (int i = 0; i < 400; ++i) {
    const int f = int(rng() % 200);
    const double scale = std::pow(0.5, 1 + int(rng() % 7));
    double v = U(rng), w = U(rng);
    if (v + w > 1) { v = 1 - v; w = 1 - w; }
    v *= scale; w *= scale;
    if (v + w < 1.0 / 128) continue;
    LoopEval e;
    ASSERT_TRUE(s.Evaluate(f, v, w, e, 1));
    deep += e.depth >= 4;
    Vec3 P, Du, Dv;
    ref.Evaluate(f, v, w, s.Net().V, &P, &Du, &Dv);
    maxNear = std::max(maxNear, (P - e.P).norm() / 2.0);  // bbox diagonal ~2
  }
  EXPECT_GT(deep, 100);
  EXPECT_LT(maxNear, 1e-10);
  // The pole itself: the limit mask against an evaluation at the corner of a pole face. The
  // evaluation nudges off the corner after maxDepth = 25 levels (Fig. 8), and round a vertex of
  // valence n each level shrinks the ring by Loop's subdominant eigenvalue 3/8 + cos(2 pi / n) / 4
  // (0.625 at n = 200, 0.5 at n = 6): the nudge is ~0.625^25 = 8e-6 of the ring's size away.
  LoopEval e;
  ASSERT_TRUE(s.Evaluate(0, 0, 0, e, 0));
  EXPECT_LT((e.P - s.VertexLimit(0)).norm(), 1e-5);
  std::printf("[valence 200 poles] far %d pts max %.2e (deriv %.2e); near the poles %d deep pts max %.2e; pole %.2e\n", a.nFar,
              a.maxFar, a.maxDer, deep, maxNear, (e.P - s.VertexLimit(0)).norm());
}
