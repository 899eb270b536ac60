// Tests for vcg_ext/core: the Embree scene and the indexed-mesh bridge.
#include <gtest/gtest.h>

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
