// The Loop surrogate .mlx scripts end to end through meshlabserver, checked against the library.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "e2e_support.h"
#include "test_support.h"
#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/io/mesh_io.h"
#include "vcg_ext/loop/loop_surface.h"
#include "vcg_ext/loop/loop_tools.h"

namespace {

vcgext::TriData ToData(const vcgext::TMesh& m) {
  vcgext::TriData d;
  EXPECT_EQ(vcgext::ImportTriangles(m, d).error, "");
  return d;
}

TEST(MlxScripts, LoopRefineOnFandiskPutsEveryVertexOnTheLimitSurface) {
  const std::string in = testsupport::SamplePath("fandisk.off");
  const std::string out = e2e::OutPath("fandisk_refined.ply");
  auto r = e2e::Meshlabserver("-i " + e2e::Q(in) + " -o " + e2e::Q(out) + " -s " +
                              e2e::Q(e2e::Script("loop_refine.mlx")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  vcgext::TMesh net, ref;
  ASSERT_EQ(vcgext::LoadMesh(in, net), "");
  ASSERT_EQ(vcgext::LoadMesh(out, ref), "");
  EXPECT_GE(ref.fn, 100000);  // the script's target
  EXPECT_LT(ref.fn, 140000);
  // Independent check: each output vertex is on the Loop surface of the net (snap distance ~0,
  // up to the float precision of the PLY file: 1e-6 of the diagonal).
  vcgext::TriData d = ToData(net);
  vcgext::LoopSurface s(d, {});
  ASSERT_TRUE(s.Ok()) << s.Error();
  vcgext::EmbreeScene scene(d);
  double diag = vcgext::BBoxDiagonal(d.V);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, ref.vn - 1);
  int far = 0;
  for (int i = 0; i < 500; ++i) {
    const auto& p = ref.vert[pick(rng)].cP();
    auto sn = vcgext::SnapToLoopSurface(s, vcgext::Vec3(p[0], p[1], p[2]), &scene);
    if (sn.distance > 1e-5 * diag) ++far;
  }
  EXPECT_LE(far, 2) << "refined vertices off the limit surface";
}

TEST(MlxScripts, LoopSnapMovesPointsOntoSurface) {
  const std::string dir = e2e::OutPath("loop_snap");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  // Net: elephant; points: its vertices pushed 0.5% of the diagonal outwards along the normal.
  vcgext::TMesh net;
  ASSERT_EQ(vcgext::LoadMesh(testsupport::SamplePath("elephant.off"), net), "");
  vcgext::TriData d = ToData(net);
  double diag = vcgext::BBoxDiagonal(d.V);
  auto N = vcgext::VertexNormals(d);
  vcgext::TMesh pts;
  vcgext::TriData moved = d;
  for (size_t i = 0; i < d.V.size(); ++i) moved.V[i] += 0.005 * diag * N[i];
  testsupport::ToVcg(moved, pts);
  ASSERT_EQ(vcgext::SaveMesh(dir + "/points.ply", pts), "");
  auto r = e2e::Meshlabserver("-i " + e2e::Q(testsupport::SamplePath("elephant.off")) + " -i " +
                              e2e::Q(dir + "/points.ply") + " -o " + e2e::Q(dir + "/snapped.ply") +
                              " -m vq -s " + e2e::Q(e2e::Script("loop_snap.mlx")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  vcgext::TMesh snapped;
  ASSERT_EQ(vcgext::LoadMesh(dir + "/snapped.ply", snapped), "");
  ASSERT_EQ(snapped.vn, int(d.V.size()));
  vcgext::LoopSurface s(d, {});
  vcgext::EmbreeScene scene(d);
  int bad = 0;
  for (int i = 0; i < snapped.vn; i += 7) {
    vcgext::Vec3 p(snapped.vert[i].P()[0], snapped.vert[i].P()[1], snapped.vert[i].P()[2]);
    // on the surface ...
    auto sn = vcgext::SnapToLoopSurface(s, p, &scene);
    if (sn.distance > 1e-5 * diag) ++bad;
    // ... and the reported distance is how far the point moved.
    vcgext::Vec3 q = moved.V[i];
    EXPECT_NEAR(snapped.vert[i].Q(), (p - q).norm(), 1e-5 * diag);
  }
  EXPECT_LE(bad, 2);
}

TEST(MlxScripts, LoopCurvatureOnSphereIsOneOverRadius) {
  const std::string dir = e2e::OutPath("loop_curv");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  const double R = 2.0;
  vcgext::TMesh m;
  testsupport::ToVcg(testsupport::Icosphere(4, R), m);
  ASSERT_EQ(vcgext::SaveMesh(dir + "/sphere.off", m), "");
  auto r = e2e::Meshlabserver("-i " + e2e::Q(dir + "/sphere.off") + " -o " + e2e::Q(dir + "/curv.ply") +
                              " -m vq vc -s " + e2e::Q(e2e::Script("loop_curvature.mlx")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  vcgext::TMesh c;
  ASSERT_EQ(vcgext::LoadMesh(dir + "/curv.ply", c), "");
  ASSERT_EQ(c.vn, m.vn);
  // Mean curvature of the Loop limit of a fine icosphere: 1/R within a few percent (the limit
  // surface is slightly inside the net), except the 12 valence-5 vertices (Loop artefact).
  int off = 0;
  for (const auto& v : c.vert)
    if (std::abs(v.cQ() * R - 1.0) > 0.05) ++off;
  EXPECT_LE(off, 12);
}

// Three triangles on the edge 0-1: the two that continue each other keep it, the third comes off
// (input_prep.h); the refined net has the three triangles' worth of faces, in two pieces.
TEST(MlxScripts, LoopRefineSeparatesTheTrianglesOfANonManifoldEdge) {
  const std::string in = e2e::OutPath("nonmanifold.off");
  {
    std::ofstream f(in);
    f << "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n";
  }
  const std::string out = e2e::OutPath("nm_out.ply");
  std::remove(out.c_str());
  auto r = e2e::Meshlabserver("-i " + e2e::Q(in) + " -o " + e2e::Q(out) + " -s " + e2e::Q(e2e::Script("loop_refine.mlx")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("separated the triangles on 1 edge"), std::string::npos) << r.output;
  vcgext::TMesh m;
  ASSERT_EQ(vcgext::LoadMesh(out, m), "");
  // each of the 3 triangles refined the same number of times: a multiple of 3 faces, at least 4 each
  EXPECT_EQ(m.fn % 3, 0);
  EXPECT_GE(m.fn, 12);
}

}  // namespace
