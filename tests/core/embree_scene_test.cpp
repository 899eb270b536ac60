// Tests for vcg_ext/core: the Embree scene and the indexed-mesh bridge.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "test_support.h"
#include "vcg_ext/core/embree_scene.h"

using vcgext::Vec3;

TEST(EmbreeScene, RayHitsPlaneAtAnalyticDistance) {
  auto m = testsupport::PlaneGrid(10, 10, 2.0);
  vcgext::EmbreeScene s(m);
  ASSERT_TRUE(s.Ok()) << s.Error();
  auto h = s.Intersect(Vec3(0.7, 1.3, 3.0), Vec3(0, 0, -1));
  ASSERT_TRUE(h.valid);
  EXPECT_NEAR(h.t, 3.0, 1e-6);
  EXPECT_NEAR((h.point - Vec3(0.7, 1.3, 0)).norm(), 0.0, 1e-6);
  EXPECT_FALSE(s.Intersect(Vec3(0.7, 1.3, 3.0), Vec3(0, 0, 1)).valid);
  // Line query finds the plane behind the origin, with a negative t.
  auto l = s.IntersectLine(Vec3(0.7, 1.3, 3.0), Vec3(0, 0, 1));
  ASSERT_TRUE(l.valid);
  EXPECT_NEAR(l.t, -3.0, 1e-6);
}

TEST(EmbreeScene, ClosestPointMatchesBruteForceOnSphere) {
  auto m = testsupport::Icosphere(3);
  vcgext::EmbreeScene s(m);
  ASSERT_TRUE(s.Ok());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-2, 2);
  for (int it = 0; it < 200; ++it) {
    Vec3 p(U(rng), U(rng), U(rng));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& f : m.F)
      best = std::min(best, (vcgext::ClosestPointOnTriangle(p, m.V[f[0]], m.V[f[1]], m.V[f[2]]) - p).norm());
    auto h = s.ClosestPoint(p);
    ASSERT_TRUE(h.valid);
    EXPECT_NEAR((h.point - p).norm(), best, 1e-5);
  }
}

// The hint face only bounds the search: with any hint (near, far, invalid) the answer's distance
// is the brute-force one, on a sphere and on the same sphere moved far from the origin (where
// Embree's float coordinates round at 1e-3 and the hint's radius must allow for it). Tolerance:
// float rounding of the coordinates (1e-5 relative to their size).
TEST(EmbreeScene, ClosestPointWithAnyHintMatchesBruteForce) {
  for (double offset : {0.0, 1e4, 1e5}) {
    auto m = testsupport::Icosphere(3);
    for (auto& v : m.V) v[0] += offset;
    vcgext::EmbreeScene s(m);
    ASSERT_TRUE(s.Ok());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-1.5, 1.5);
    std::uniform_int_distribution<int> F(0, int(m.F.size()) - 1);
    int previous = -1;
    for (int it = 0; it < 300; ++it) {
      const Vec3 p(offset + U(rng), U(rng), U(rng));
      double best = std::numeric_limits<double>::infinity();
      for (const auto& f : m.F)
        best = std::min(best, (vcgext::ClosestPointOnTriangle(p, m.V[f[0]], m.V[f[1]], m.V[f[2]]) - p).norm());
      const double tol = 1e-5 + 3e-7 * offset;  // a float ulp of the coordinates, 2.5x
      for (int hint : {-1, previous, F(rng), int(m.F.size()) + 5}) {
        const auto h = s.ClosestPoint(p, std::numeric_limits<double>::infinity(), hint);
        ASSERT_TRUE(h.valid);
        EXPECT_NEAR((h.point - p).norm(), best, tol) << "hint " << hint << " offset " << offset;
      }
      // with a finite range too: the answer when it lies within the range
      const auto r = s.ClosestPoint(p, 0.3, F(rng));
      if (best < 0.3 - tol) {
        ASSERT_TRUE(r.valid);
        EXPECT_NEAR((r.point - p).norm(), best, tol);
      }
      previous = s.ClosestPoint(p).face;
    }
  }
}

// The callback skips a triangle whose box is farther than the best distance so far (embree_scene.cpp,
// PointQueryFunc): the answer must be the brute-force one bit for bit (same face, same point), also
// for query points within 1e-12 of the surface, where the skip's rounding margin matters, and on a
// sphere far from the origin. The brute force uses the float-rounded query point, as Embree does.
TEST(EmbreeScene, ClosestPointIsExactlyTheBruteForceAnswerNearTheSurface) {
  for (double offset : {0.0, 1e4}) {
    auto m = testsupport::Icosphere(4);
    for (auto& v : m.V) v[0] += offset;
    vcgext::EmbreeScene s(m);
    ASSERT_TRUE(s.Ok());
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> F(0, int(m.F.size()) - 1);
    std::uniform_real_distribution<double> U(0.05, 0.9), E(-12, -1);
    int exact = 0;
    for (int it = 0; it < 400; ++it) {
      const auto& f = m.F[F(rng)];
      const double a = U(rng), b = (1 - a) * U(rng);
      const Vec3 n = (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]).normalized();
      const Vec3 on = (1 - a - b) * m.V[f[0]] + a * m.V[f[1]] + b * m.V[f[2]];
      const Vec3 q = on + (it % 2 ? 1 : -1) * std::pow(10.0, E(rng)) * n;
      // Embree's query point is float. volatile: the rounding must happen
      // (without it this test saw the unrounded point reach the brute force).
      volatile float qf[3] = {float(q[0]), float(q[1]), float(q[2])};
      const Vec3 p(qf[0], qf[1], qf[2]);
      double best = std::numeric_limits<double>::infinity();
      int bestFace = -1;
      Vec3 bestPoint;
      for (size_t g = 0; g < m.F.size(); ++g) {
        const auto& t = m.F[g];
        const Vec3 c = vcgext::ClosestPointOnTriangle(p, m.V[t[0]], m.V[t[1]], m.V[t[2]]);
        if ((c - p).squaredNorm() < best) {
          best = (c - p).squaredNorm();
          bestFace = int(g);
          bestPoint = c;
        }
      }
      const auto h = s.ClosestPoint(p);
      ASSERT_TRUE(h.valid);
      EXPECT_EQ((h.point - p).squaredNorm(), best) << it << " offset " << offset;
      if (h.face == bestFace) {
        EXPECT_EQ(h.point, bestPoint) << it;
        ++exact;
      }
    }
    EXPECT_GT(exact, 390) << "offset " << offset;  // other faces only on exact ties (a shared edge)
  }
}

// NearestOnLine (the projection phi with fewer rays) against a brute-force double-precision
// line/triangle search, on two nested spheres (several sheets on most lines), for every guess of
// the side, several windows and ray lengths: the guess and the window may only change the ray
// count, never the answer. Tolerance 1e-5: Embree works in float on coordinates of size 1.
TEST(EmbreeScene, NearestOnLineMatchesBruteForceForAnyGuessAndWindow) {
  auto outer = testsupport::Icosphere(3);
  auto inner = testsupport::Icosphere(3);
  vcgext::TriData m = outer;
  const int off = int(m.V.size());
  for (const Vec3& v : inner.V) m.V.push_back(0.93 * v);
  for (const auto& f : inner.F) m.F.push_back({f[0] + off, f[2] + off, f[1] + off});
  vcgext::EmbreeScene s(m);
  ASSERT_TRUE(s.Ok()) << s.Error();
  // nearest hit along +d (t >= 0) and along -d (t < 0) within maxDist; *tBest: the nearer one
  auto brute = [&](const Vec3& c, const Vec3& d, double maxDist, double* tBest, double* gap) {
    double tp = std::numeric_limits<double>::infinity(), tn = -tp;
    for (const auto& f : m.F) {
      const Vec3 &a = m.V[f[0]], &b = m.V[f[1]], &cc = m.V[f[2]];
      Vec3 e1 = b - a, e2 = cc - a, p = d.cross(e2);
      double det = e1.dot(p);
      if (std::abs(det) < 1e-14) continue;
      Vec3 tv = c - a;
      double u = tv.dot(p) / det;
      Vec3 q = tv.cross(e1);
      double v = d.dot(q) / det;
      if (u < -1e-12 || v < -1e-12 || u + v > 1 + 1e-12) continue;
      double t = e2.dot(q) / det;
      if (std::abs(t) > maxDist) continue;
      if (t >= 0) tp = std::min(tp, t);
      else tn = std::max(tn, t);
    }
    *tBest = tp <= -tn ? tp : tn;
    *gap = std::abs(tp + tn);  // difference of the two sides' distances (ties are ambiguous)
    return std::isfinite(*tBest);
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1), R(0.88, 1.04);
  const double maxDists[] = {0.02, 0.3, 3.0};
  const double windows[] = {0.0, 0.001, 0.01, 0.2};
  int checked = 0;
  for (int it = 0; it < 300; ++it) {
    Vec3 dir(U(rng), U(rng), U(rng));
    if (dir.norm() < 0.1) continue;
    dir.normalize();
    Vec3 c = R(rng) * dir;  // near the sheets
    Vec3 d = it % 2 ? Vec3(dir + 0.3 * Vec3(U(rng), U(rng), U(rng))).normalized()
                    : Vec3(U(rng), U(rng), U(rng)).normalized();
    for (double maxDist : maxDists) {
      double tRef = 0, gap = 0;
      const bool ref = brute(c, d, maxDist, &tRef, &gap);
      // skip the float-ambiguous cases: a hit at the end of the range, or a near tie of the sides
      if (ref && (std::abs(std::abs(tRef) - maxDist) < 1e-5 || gap < 1e-5)) continue;
      for (double w : windows)
        for (int guess : {-1, 0, 1}) {
          signed char side = static_cast<signed char>(guess);
          auto h = s.NearestOnLine(c, d, maxDist, w, guess ? &side : nullptr);
          ASSERT_EQ(h.valid, ref) << "it " << it << " maxDist " << maxDist << " window " << w << " guess " << guess;
          if (!ref) continue;
          EXPECT_NEAR(h.t, tRef, 1e-5) << "it " << it << " maxDist " << maxDist << " window " << w << " guess " << guess;
          EXPECT_NEAR((h.point - (c + h.t * d)).norm(), 0.0, 1e-5);
          if (guess) { EXPECT_EQ(side, h.t < 0 ? -1 : 1); }
          ++checked;
        }
    }
  }
  EXPECT_GT(checked, 2000);
}

// The boundary query (a BVH over the boundary edges) gives the point a loop over every boundary
// edge gives: a sphere with 40 holes plus 300 floating two-triangle specks (thousands of edges),
// points anywhere around it, near the holes' rims and on them; a closed mesh has no boundary.
TEST(EmbreeScene, ClosestBoundaryPointMatchesBruteForce) {
  vcgext::TriData m = testsupport::SphereWithHoles(40);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 300; ++i) {
    const int b = int(m.V.size());
    const Vec3 c(u(rng), u(rng), u(rng));
    m.V.insert(m.V.end(), {c, c + Vec3(0.01, 0, 0), c + Vec3(0.01, 0.01, 0.005), c + Vec3(0, 0.01, 0)});
    m.F.push_back({b, b + 1, b + 2});
    m.F.push_back({b, b + 2, b + 3});
  }
  const vcgext::EmbreeScene scene(m);
  ASSERT_TRUE(scene.Ok());
  const auto& edges = scene.BoundaryEdges();
  EXPECT_EQ(edges, vcgext::BoundaryHalfEdges(m));
  ASSERT_GT(edges.size(), 1200u);
  auto brute = [&](const Vec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : edges) {
      const Vec3 d = m.V[b] - m.V[a];
      const double t = std::clamp((p - m.V[a]).dot(d) / d.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (m.V[a] + t * d - p).norm());
    }
    return best;
  };
  std::vector<Vec3> queries;
  for (int i = 0; i < 400; ++i) queries.push_back(Vec3(u(rng), u(rng), u(rng)));
  for (size_t i = 0; i < edges.size(); i += 7) {  // on and near the rims
    const Vec3 &a = m.V[edges[i].first], &b = m.V[edges[i].second];
    queries.push_back(0.3 * a + 0.7 * b);
    queries.push_back(a + 1e-4 * Vec3(u(rng), u(rng), u(rng)));
  }
  for (const Vec3& p : queries) {
    const vcgext::EmbreeScene::Hit h = scene.ClosestBoundaryPoint(p);
    ASSERT_TRUE(h.valid);
    const double d = brute(p);
    EXPECT_NEAR(h.t, d, 1e-12) << p.transpose();
    EXPECT_NEAR((h.point - p).norm(), d, 1e-12);
    const auto& [a, b] = edges[size_t(h.face)];  // the point lies on the edge it names
    const Vec3 d2 = m.V[b] - m.V[a];
    EXPECT_NEAR((m.V[a] + h.u * d2 - h.point).norm(), 0.0, 1e-12);
  }
  const vcgext::EmbreeScene closed(testsupport::Icosphere(2));
  EXPECT_TRUE(closed.BoundaryEdges().empty());
  EXPECT_FALSE(closed.ClosestBoundaryPoint(Vec3(0, 0, 0)).valid);
}

// Embree works in float and its ray-triangle test clamps its determinant below 1e-18: on a mesh a
// few 1e-8 across every hit came back at a triangle corner (u = v = 0), and beyond ~1e15 rays hit
// nothing. EmbreeScene hands Embree a copy scaled by a power of two (exact) outside
// [kMinUnscaledDiagonal, kMaxUnscaledDiagonal]: every query must then give the unit mesh's answer
// scaled, bit for bit (the hit faces and barycentrics equal, distances and points times the scale).
TEST(EmbreeScene, AnswersDoNotDependOnTheMeshScale) {
  const auto unit = testsupport::SphereWithHoles(3);  // boundaries for ClosestBoundaryPoint
  const vcgext::EmbreeScene s1(unit);
  ASSERT_TRUE(s1.Ok()) << s1.Error();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.3, 1.3);
  std::vector<Vec3> pts, dirs;
  for (int i = 0; i < 300; ++i) {
    pts.emplace_back(U(rng), U(rng), U(rng));
    dirs.push_back(Vec3(U(rng), U(rng), U(rng)).normalized());
  }
  for (int e : {-100, -60, -40, -28, 40, 50, 55}) {
    SCOPED_TRACE("scale 2^" + std::to_string(e));
    const double k = std::ldexp(1.0, e);
    auto m = unit;
    for (auto& v : m.V) v *= k;
    const vcgext::EmbreeScene s(m);
    ASSERT_TRUE(s.Ok()) << s.Error();
    int hits = 0;
    auto same = [&](const vcgext::EmbreeScene::Hit& a, const vcgext::EmbreeScene::Hit& b, const char* what) {
      ASSERT_EQ(a.valid, b.valid) << what;
      if (!a.valid) return;
      ++hits;
      EXPECT_EQ(a.face, b.face) << what;
      EXPECT_EQ(a.u, b.u) << what;
      EXPECT_EQ(a.v, b.v) << what;
      EXPECT_EQ(a.t * k, b.t) << what;
      EXPECT_EQ(a.point * k, b.point) << what;
    };
    for (size_t i = 0; i < pts.size(); ++i) {
      const Vec3 p = pts[i] * k;
      same(s1.Intersect(pts[i], dirs[i]), s.Intersect(p, dirs[i]), "Intersect");
      same(s1.Intersect(pts[i], dirs[i], 0.1, 0.8), s.Intersect(p, dirs[i], 0.1 * k, 0.8 * k), "Intersect [0.1, 0.8]");
      same(s1.NearestOnLine(pts[i], dirs[i], 0.5, 0.01), s.NearestOnLine(p, dirs[i], 0.5 * k, 0.01 * k), "NearestOnLine");
      same(s1.ClosestPoint(pts[i]), s.ClosestPoint(p), "ClosestPoint");
      same(s1.ClosestPoint(pts[i], 0.3, int(i)), s.ClosestPoint(p, 0.3 * k, int(i)), "ClosestPoint with a hint");
      same(s1.ClosestBoundaryPoint(pts[i]), s.ClosestBoundaryPoint(p), "ClosestBoundaryPoint");
    }
    EXPECT_GT(hits, 1000);
  }
}

TEST(ImportTriangles, RejectsBadLayersAndLeavesThemUntouched) {
  vcgext::TMesh m;
  vcgext::TriData d;
  EXPECT_NE(vcgext::ImportTriangles(m, d).error.find("empty"), std::string::npos);
  vcg::tri::Allocator<vcgext::TMesh>::AddVertices(m, 3);
  EXPECT_NE(vcgext::ImportTriangles(m, d).error.find("point cloud"), std::string::npos);
  testsupport::ToVcg(testsupport::PlaneGrid(2, 2), m);
  m.vert[4].P()[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(vcgext::ImportTriangles(m, d).error.find("NaN"), std::string::npos);
  testsupport::ToVcg(testsupport::PlaneGrid(2, 2), m);
  m.face[0].SetF(1);
  m.face[1].SetF(2);
  EXPECT_NE(vcgext::ImportTriangles(m, d).error.find("polygonal"), std::string::npos);
  EXPECT_EQ(vcgext::ImportTriangles(m, d, true).error, "");
}
