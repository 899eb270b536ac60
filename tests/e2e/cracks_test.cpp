// Cracks wider than the working copy's seam weld (docs/robustness.md "Cracks"): the warning's
// advice, run through meshlabserver, closes them. fandisk.off cut in two along x = its median
// (each half with its own copies of the cut's vertices, the right half's moved by 1e-5 of the
// diagonal: an unwelded seam no exact weld closes) is warned about by the simplification, and
// MeshLab's Merge Close Vertices at the distance the warning gives, run before the same script,
// leaves no crack warning and the clean part's cage (measured 2026-12-06 on fandisk with 20 % of
// its edges cracked so: 4 365 patches before the weld, 430 after, the clean part's 430).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include "e2e_support.h"
#include "test_support.h"
#include "vcg_ext/io/mesh_io.h"

namespace {

// `m` with the faces whose centroid lies right of the median x given their own copies of the
// vertices they share with the others, moved by `offset`; saved to `path` (SaveMesh's error).
std::string WriteCutInTwo(const vcgext::TriData& m, const vcgext::Vec3& offset, const std::string& path) {
  auto centroidX = [&](const vcgext::Tri& f) { return (m.V[size_t(f[0])] + m.V[size_t(f[1])] + m.V[size_t(f[2])]).x() / 3; };
  std::vector<double> xs;
  for (const auto& f : m.F) xs.push_back(centroidX(f));
  std::nth_element(xs.begin(), xs.begin() + long(xs.size() / 2), xs.end());
  const double cut = xs[xs.size() / 2];
  std::vector<int> side(m.V.size(), 0);  // bit 0: used by a left face, bit 1: by a right one
  for (const auto& f : m.F)
    for (int v : f) side[size_t(v)] |= centroidX(f) > cut ? 2 : 1;
  vcgext::TriData out = m;
  std::vector<int> copy(m.V.size(), -1);
  for (size_t v = 0; v < m.V.size(); ++v)
    if (side[v] == 3) {
      copy[v] = int(out.V.size());
      out.V.push_back(m.V[v] + offset);
    }
  for (size_t i = 0; i < m.F.size(); ++i)
    if (centroidX(m.F[i]) > cut)
      for (int& v : out.F[i])
        if (copy[size_t(v)] >= 0) v = copy[size_t(v)];
  vcgext::TMesh t;
  testsupport::ToVcg(out, t);
  return vcgext::SaveMesh(path, t);
}

}  // namespace

TEST(Cracks, WarningsMergingDistanceClosesAnUnweldedSeam) {
  const vcgext::TriData fandisk = testsupport::LoadSample("fandisk.off");
  const double diag = vcgext::BBoxDiagonal(fandisk.V);
  const std::string cracked = e2e::OutPath("cracks_fandisk.off");
  ASSERT_EQ(WriteCutInTwo(fandisk, 1e-5 * diag * vcgext::Vec3(1, 2, 3).normalized(), cracked), "");
  const std::string script = e2e::Script("quad_simplification.mlx");

  const auto before = e2e::Meshlabserver("-i " + e2e::Q(cracked) + " -s " + e2e::Q(script));
  ASSERT_EQ(before.exitCode, 0) << before.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(before.output, m,
                                std::regex("Fitmap Quad Simplification: ([0-9]+) boundary vertices lie near another "
                                           "boundary's.*?merging distance of ([0-9.e+-]+) ")))
      << before.output;
  EXPECT_GE(std::stoi(m[1]), 20) << m[0];  // both sides of a cut across the part
  const double distance = std::stod(m[2]);
  EXPECT_GT(distance, 1e-5 * diag);  // closes the gap ...
  EXPECT_LT(distance, 1e-3 * diag);  // ... and stays far below fandisk's edges (~1 % of the diagonal)

  char merge[400];
  std::snprintf(merge, sizeof merge,
                " <filter name=\"Merge Close Vertices\">\n"
                "  <Param type=\"RichAbsPerc\" value=\"%.6g\" min=\"0\" max=\"%.6g\" name=\"Threshold\"/>\n"
                " </filter>\n",
                distance, diag / 100);
  const auto after = e2e::Meshlabserver(
      "-i " + e2e::Q(cracked) + " -s " +
      e2e::Q(e2e::ScriptWithFirstFilter("quad_simplification.mlx", merge, "cracks_welded.mlx")));
  ASSERT_EQ(after.exitCode, 0) << after.output;
  EXPECT_EQ(after.output.find("lie near another boundary's"), std::string::npos) << after.output;
  const auto clean =
      e2e::Meshlabserver("-i " + e2e::Q(testsupport::SamplePath("fandisk.off")) + " -s " + e2e::Q(script));
  ASSERT_EQ(clean.exitCode, 0) << clean.output;
  const int welded = e2e::LoggedPatches(after.output), whole = e2e::LoggedPatches(clean.output);
  ASSERT_GT(whole, 0) << clean.output;
  EXPECT_NEAR(welded, whole, 0.05 * whole) << "welded " << welded << ", clean " << whole;
}
