// quad_simplification.mlx and pipeline.mlx end to end on real scans.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include "e2e_support.h"
#include "test_support.h"
#include "tests/quad/quad_test_util.h"
#include "vcg_ext/fit/fit_io.h"
#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/io/mesh_io.h"

namespace {

struct QuadStats {
  int V = 0, E = 0, F = 0, valence2 = 0, irregular = 0, boundaryEdges = 0;
};

QuadStats Stats(const vcgext::QuadData& q) {
  QuadStats s;
  std::map<std::pair<int, int>, int> edges;
  std::vector<int> val(q.V.size(), 0);
  std::vector<char> used(q.V.size(), 0);
  for (const auto& f : q.F)
    for (int k = 0; k < 4; ++k) {
      used[f[k]] = 1;
      auto e = std::minmax(f[k], f[(k + 1) % 4]);
      if (edges[e]++ == 0) {
        ++val[e.first];
        ++val[e.second];
      }
    }
  for (size_t i = 0; i < q.V.size(); ++i)
    if (used[i]) {
      ++s.V;
      s.valence2 += val[i] == 2 ? 1 : 0;
      s.irregular += val[i] != 4 ? 1 : 0;
    }
  s.E = int(edges.size());
  s.F = int(q.F.size());
  for (const auto& e : edges) s.boundaryEdges += e.second == 1 ? 1 : 0;
  return s;
}

using e2e::JsonNumber;
using e2e::Slurp;

TEST(MlxScripts, QuadSimplificationOnBunnyIsAValidCoarseQuadMesh) {
  const std::string in = testsupport::SamplePath("bunny00.off");
  const std::string out = e2e::OutPath("bunny_quads.ply");
  auto r = e2e::Meshlabserver("-i " + e2e::Q(in) + " -o " + e2e::Q(out) + " -l 1 -m ff -s " +
                              e2e::Q(e2e::Script("quad_simplification.mlx")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  vcgext::TMesh m;
  ASSERT_EQ(vcgext::LoadMesh(out, m), "");
  vcgext::QuadData q;
  ASSERT_EQ(vcgext::ImportQuads(m, q), "");  // pure quads in MeshLab's faux-edge convention
  QuadStats s = Stats(q);
  EXPECT_EQ(s.V - s.E + s.F, 2) << "bunny00 is a closed genus-0 surface";
  EXPECT_EQ(s.boundaryEdges, 0);
  EXPECT_EQ(s.valence2, 0) << "doublets must be removed";
  // Conciseness target at tau = 1% (issue 3: at most ~550; paper 506) and not collapsed away.
  EXPECT_LE(s.F, 550);
  EXPECT_GE(s.F, 50);
  // The log line reports the same counts as the layer.
  std::smatch mm;
  ASSERT_TRUE(std::regex_search(r.output, mm, std::regex("-> ([0-9]+) patches, ([0-9]+) irregular vertices")))
      << r.output;
  EXPECT_EQ(std::stoi(mm[1]), s.F);
  EXPECT_EQ(std::stoi(mm[2]), s.irregular);
}

TEST(RunPipeline, WholePipelineOnElephantWritesConsistentOutputs) {
  const std::string outdir = e2e::OutPath("pipeline_elephant_full");
  auto r = e2e::Run("FITMAP_SKIP_SETUP=1 " + e2e::Q(e2e::Script("run_pipeline.sh")) + " --tau 10 --normal-map " +
                    e2e::Q(testsupport::SamplePath("elephant.off")) + " " + e2e::Q(outdir));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* f : {"fitmap.ply", "control.obj", "control.mtl", "control.ply", "limit.ply", "displaced.ply",
                        "displacement.png", "displacement.json", "normal.png", "report.json"})
    EXPECT_TRUE(std::ifstream(outdir + "/" + f).good()) << f;
  const std::string json = Slurp(outdir + "/report.json");
  // The printed report is the file.
  EXPECT_NE(r.output.find(json.substr(0, 40)), std::string::npos);
  // report.json agrees with the control mesh written next to it.
  vcgext::TMesh cm;
  ASSERT_EQ(vcgext::LoadMesh(outdir + "/control.ply", cm), "");
  vcgext::QuadData q;
  ASSERT_EQ(vcgext::ImportQuads(cm, q), "");
  QuadStats s = Stats(q);
  EXPECT_EQ(JsonNumber(json, "patches"), s.F);
  EXPECT_EQ(JsonNumber(json, "irregular_vertices"), s.irregular);
  // Every stage is timed and the total is their sum.
  double sum = 0;
  for (const char* k : {"fitmaps", "tri_to_quad", "initial_fit", "simplification", "fit", "tessellate", "bake", "metrics", "fit_setup"}) {
    double t = JsonNumber(json, k);
    EXPECT_TRUE(std::isfinite(t) && t >= 0) << k;
    sum += t;
  }
  // the equalized layout's count pass (docs/quad.md "Layout"), on by default
  ASSERT_NE(json.find("\"count_pass\""), std::string::npos) << json;
  sum += JsonNumber(json, "count_pass");
  EXPECT_NEAR(JsonNumber(json, "total"), sum, 1e-6 + 1e-6 * sum);  // rounding of the printed values only
  EXPECT_GT(JsonNumber(json, "peak_memory_mb"), 10);
  // Peak memory per stage (one entry per filter before the fit, then the fit's stages): each
  // holds at least the meshes (> 10 MB with MeshLab loaded) and at most the process peak.
  const size_t perStage = json.find("\"peak_memory_mb_per_stage\"");
  ASSERT_NE(perStage, std::string::npos) << json;
  const std::string stages = json.substr(perStage, json.find('}', perStage) - perStage);
  for (const char* k : {"quad_simplification", "fit", "tessellate", "bake", "metrics"}) {
    const double mb = JsonNumber(stages, k);
    EXPECT_GT(mb, 10) << k << ": " << stages;
    EXPECT_LE(mb, JsonNumber(json, "peak_memory_mb") + 1e-6) << k << ": " << stages;
  }
  // Errors are finite and ordered: displacement restores detail.
  EXPECT_LT(JsonNumber(json, "rms_displaced_permille"), JsonNumber(json, "rms_limit_permille"));
  EXPECT_LT(JsonNumber(json, "unprojectable_pct"), 5.0);
  // The limit layer's quality is its signed distance to the input: |q| <= max limit error.
  vcgext::TMesh lim;
  ASSERT_EQ(vcgext::LoadMesh(outdir + "/limit.ply", lim), "");
  EXPECT_EQ(lim.fn, 2 * 8 * 8 * s.F);
}

// A pure-quad layer (a quad remesher's output) is simplified from its quads; with a few of its quads
// stored reversed against their neighbours (parts merged, an exporter's clockwise faces) it still is,
// read oriented as most of its faces, where it fell back to its triangles before (the working copy
// re-oriented them and its quads no longer matched), into as many patches and irregular vertices
// as the layer stored whole (not the same layout: the reversed quads start at other corners, and
// the greedy order follows the order it is given; docs/robustness.md "Faces stored reversed").
TEST(MlxScripts, QuadSimplificationReadsQuadsStoredReversedAsQuads) {
  const std::string dir = e2e::OutPath("quads_reversed");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  vcgext::QuadData cage = quadtest::CubeSphere(20);  // 2 400 quads on the unit sphere, made bumpy:
  for (vcgext::Vec3& v : cage.V) v *= 1 + 0.08 * std::sin(4 * v[0]) * std::sin(4 * v[1]) * std::sin(4 * v[2]);
  std::smatch mm[2];
  std::string log[2];
  for (int reversed : {0, 1}) {
    if (reversed)
      for (int f : {7, 800, 1999}) std::reverse(cage.F[f].begin(), cage.F[f].end());
    const std::string in = dir + (reversed ? "/reversed.ply" : "/whole.ply");
    ASSERT_EQ(vcgext::WriteQuadPly(in, cage), "");
    auto r = e2e::Meshlabserver("-i " + e2e::Q(in) + " -o " + e2e::Q(dir + "/out.ply") + " -s " +
                                e2e::Q(e2e::Script("quad_simplification.mlx")));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    log[reversed] = r.output;
    EXPECT_NE(r.output.find("the layer is pure quads: simplifying its quads"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("stored reversed") != std::string::npos, reversed == 1) << r.output;
    ASSERT_TRUE(std::regex_search(log[reversed], mm[reversed],
                                  std::regex("-> ([0-9]+) patches, ([0-9]+) irregular vertices")))
        << r.output;
  }
  EXPECT_NE(log[1].find("6 of the layer's triangles were stored reversed against their neighbours"), std::string::npos)
      << log[1];
  // The same quads, three of them starting at another corner: as many patches and irregular vertices.
  EXPECT_EQ(mm[1][1], mm[0][1]);
  EXPECT_EQ(mm[1][2], mm[0][2]);
}

}  // namespace
