// Far spikes (vcg_ext/core/far_spikes.h): a scanner's wild point at the tip of needle triangles,
// far outside the model's box, is refused by the quad pipeline's working copy; spikes inside the
// box, big flat triangles (a ground plane, a CAD face) and pieces far apart are not spikes.
#include <gtest/gtest.h>

#include <string>

#include "test_support.h"
#include "vcg_ext/core/far_spikes.h"

using vcgext::Vec3;

namespace {
vcgext::TriData WithVertexAt(vcgext::TriData t, int v, const Vec3& p) {
  t.V[size_t(v)] = p;
  return t;
}
}  // namespace

TEST(FarSpikes, AWildVertexFarOutsideTheModelIsAnError) {
  const auto sphere = testsupport::Icosphere(4);  // radius 1, diagonal 3.46
  for (double away : {10.0, 1e3, 1e6}) {
    SCOPED_TRACE(away);
    const auto t = WithVertexAt(sphere, 100, sphere.V[100] + away * Vec3(0.8, 0.5, 0.3));
    const vcgext::FarSpikes s = vcgext::FindFarSpikes(t);
    EXPECT_EQ(s.count, 1);
    EXPECT_EQ(s.first, 100);
    EXPECT_NEAR(s.diagWithout, vcgext::BBoxDiagonal(sphere.V), 0.05);  // the sphere's box, less the vertex
    EXPECT_GT(s.edgeFactor, 10 * away);  // the median edge is 0.077
    std::vector<int> layerIndex(t.V.size());
    for (size_t i = 0; i < layerIndex.size(); ++i) layerIndex[i] = int(i) + 7;  // as if 7 vertices were dropped
    const std::string e = vcgext::FarSpikesError(t, &layerIndex);
    EXPECT_NE(e.find("1 vertex lies far from the rest of the surface (first: vertex 107)"), std::string::npos) << e;
    EXPECT_NE(e.find("Select Faces with edges longer than"), std::string::npos) << e;
  }
}

TEST(FarSpikes, SpikesInsideTheBoxFlatTrianglesAndFarPiecesAreNot) {
  const auto sphere = testsupport::Icosphere(4);
  // pushed out 30 % (corpus scan_spikes.off) or 2 radii: within a factor 2 of the box, no error
  for (double f : {1.3, 3.0}) {
    const auto t = WithVertexAt(sphere, 100, f * sphere.V[100]);
    EXPECT_TRUE(vcgext::FarSpikesError(t).empty()) << f;
  }
  // a ground plane of two triangles 100 times the sphere's size below it: its corners' edges are
  // long, but so are the edges opposite them (no needles)
  auto scene = sphere;
  const int b = int(scene.V.size());
  for (Vec3 c : {Vec3(-100, -100, -1.5), Vec3(100, -100, -1.5), Vec3(100, 100, -1.5), Vec3(-100, 100, -1.5)})
    scene.V.push_back(c);
  scene.F.push_back({b, b + 1, b + 2});
  scene.F.push_back({b, b + 2, b + 3});
  EXPECT_EQ(vcgext::FindFarSpikes(scene).count, 0);
  EXPECT_TRUE(vcgext::FarSpikesError(scene).empty());
  // two spheres 1 000 radii apart: normal edges everywhere
  auto two = sphere;
  for (const auto& f : sphere.F) two.F.push_back({f[0] + b, f[1] + b, f[2] + b});
  for (const auto& v : sphere.V) two.V.push_back(v + Vec3(1000, 0, 0));
  EXPECT_EQ(vcgext::FindFarSpikes(two).count, 0);
}

// The fix the error names (PyMeshLab checked on bunny00 with a wild vertex: 6 faces selected, the
// box back to the bunny's): without the needle triangles, nothing is refused.
TEST(FarSpikes, RemovingTheNeedlesClearsTheError) {
  const auto sphere = testsupport::Icosphere(4);
  auto t = WithVertexAt(sphere, 100, sphere.V[100] + Vec3(2000, 600, 400));
  ASSERT_FALSE(vcgext::FarSpikesError(t).empty());
  const double longer = 0.5 * vcgext::FindFarSpikes(t).shortestEdge;
  std::vector<vcgext::Tri> kept;
  for (const auto& f : t.F) {
    bool needle = false;
    for (int k = 0; k < 3; ++k) needle = needle || (t.V[f[k]] - t.V[f[(k + 1) % 3]]).norm() > longer;
    if (!needle) kept.push_back(f);
  }
  EXPECT_EQ(t.F.size() - kept.size(), 6u);  // the wild vertex's fan (valence 6 on a level-4 icosphere)
  t.F = kept;
  t.V[100] = sphere.V[100];  // the vertex is in no face now; its position no longer counts
  EXPECT_TRUE(vcgext::FarSpikesError(t).empty());
}
