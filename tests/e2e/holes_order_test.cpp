// A holed scan stored in another face order (docs/quad.md "Coverage judged after the fit"): the
// same surface must give about the same cage. elephant.off with every 50th face deleted (holes
// sharing no vertex, ~2 % of the faces), once as it is and once with every 20th face stored
// reversed (the working copy turns them back; each then starts at another corner). The coverage
// guard's area trigger fires on both (the interpolating limit's outline shrinks inside the hole
// rims); judged on the fitted limit, both cages are kept instead of one being laid out again with
// twice the patches (found on the breakage runs' holed elephant: 689 patches as stored, 1 330 with
// 5 % of its faces reversed). Measured 2026-12-06: 659 and 698 patches. Since 2026-12-07 such
// holes are closed for the layout by default (close_holes.h); the guard's path is tested with
// them left open (closeHoles 0). The bound, 15 %, is the
// spread another order gives on clean scans (docs/robustness.md "Another vertex and face order":
// -5 ... +14 %).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>

#include "e2e_support.h"
#include "test_support.h"
#include "vcg_ext/io/mesh_io.h"

namespace {
// elephant.off with every 50th face deleted where no neighbouring hole shares its corners;
// reverse: every 20th remaining face stored with the opposite orientation, (a, b, c) as (c, b, a)
// (turned back, it starts at another corner than before).
std::string HoledElephant(bool reverse, const std::string& name) {
  vcgext::TriData holed = testsupport::WithIsolatedHoles(testsupport::LoadSample("elephant.off"), 50);
  if (reverse)
    for (size_t f = 7; f < holed.F.size(); f += 20) std::swap(holed.F[f][0], holed.F[f][2]);
  vcgext::TMesh m;
  testsupport::ToVcg(holed, m);
  const std::string path = e2e::OutPath(name);
  EXPECT_EQ(vcgext::SaveMesh(path, m), "");
  return path;
}
// quad_simplification.mlx with the holes left open (closeHoles 0): the coverage guard's path
std::string ScriptHolesOpen() {
  std::string s = e2e::Slurp(e2e::Script("quad_simplification.mlx"));
  const std::string from = R"(value="2" name="closeHoles")";
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << "quad_simplification.mlx closes holes below 2 %";
  if (at != std::string::npos) s.replace(at, from.size(), R"(value="0" name="closeHoles")");
  const std::string path = e2e::OutPath("quad_simplification_holes_open.mlx");
  std::ofstream(path) << s;
  return path;
}
}  // namespace

// Holes left open (closeHoles 0): the coverage guard's area trigger fires on both orders, the
// fitted limit reaches the input, no relayout, counts within 15 % (docs/quad.md "Coverage judged
// after the fit").
TEST(HolesOrder, HoledScanGivesAboutTheSameCageInAnotherFaceOrder) {
  const std::string script = ScriptHolesOpen();
  int patches[2] = {0, 0};
  for (int reverse = 0; reverse < 2; ++reverse) {
    const std::string in = HoledElephant(reverse, reverse ? "holed_elephant_reversed.off" : "holed_elephant.off");
    const auto r = e2e::Meshlabserver("-i " + e2e::Q(in) + " -s " + e2e::Q(script));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    if (reverse) {
      EXPECT_NE(r.output.find("re-oriented"), std::string::npos) << r.output;
    }
    // nothing closed (the log line's start: the holes warning's advice also says "for the layout")
    EXPECT_EQ(r.output.find("Fitmap Quad Simplification: closed "), std::string::npos) << r.output;
    // the guard's area trigger fired and the fitted limit reached the input: no relayout
    EXPECT_NE(r.output.find("fitted, it leaves"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("laid out again with"), std::string::npos) << r.output;
    patches[reverse] = e2e::LoggedPatches(r.output);
    ASSERT_GT(patches[reverse], 0) << r.output;
  }
  std::printf("holed elephant, holes open: %d patches as stored, %d with every 20th face reversed\n", patches[0],
              patches[1]);
  EXPECT_LE(std::max(patches[0], patches[1]), 1.15 * std::min(patches[0], patches[1]));
}

// By default the small holes are closed for the layout (close_holes.h): both orders log every
// hole closed and give the clean scan's cage within 15 % (the spread another order gives on clean
// scans), fewer patches than with the holes open (each hole kept a ring of patches).
TEST(HolesOrder, HoledScanClosedForTheLayoutGivesTheCleanScansCage) {
  const std::string script = e2e::Script("quad_simplification.mlx");
  const auto c = e2e::Meshlabserver("-i " + e2e::Q(testsupport::SamplePath("elephant.off")) + " -s " + e2e::Q(script));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  const int clean = e2e::LoggedPatches(c.output);
  const vcgext::TriData full = testsupport::LoadSample("elephant.off");
  const size_t holes = full.F.size() - testsupport::WithIsolatedHoles(full, 50).F.size();
  const std::string closed = "closed " + std::to_string(holes) + " of the layer's " + std::to_string(holes) + " holes";
  const auto o = e2e::Meshlabserver("-i " + e2e::Q(HoledElephant(false, "holed_elephant_open.off")) + " -s " +
                                    e2e::Q(ScriptHolesOpen()));
  ASSERT_EQ(o.exitCode, 0) << o.output;
  const int open = e2e::LoggedPatches(o.output);
  for (int reverse = 0; reverse < 2; ++reverse) {
    const std::string in = HoledElephant(reverse, reverse ? "holed_elephant_c_reversed.off" : "holed_elephant_c.off");
    const auto r = e2e::Meshlabserver("-i " + e2e::Q(in) + " -s " + e2e::Q(script));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find(closed), std::string::npos) << closed << "\n" << r.output;
    EXPECT_EQ(r.output.find("fitted, it leaves"), std::string::npos) << r.output;  // no hole rim for the guard
    const int patches = e2e::LoggedPatches(r.output);
    std::printf("holed elephant, holes closed%s: %d patches (clean %d, holes open %d)\n",
                reverse ? ", every 20th face reversed" : "", patches, clean, open);
    EXPECT_NEAR(patches, clean, 0.15 * clean);
    EXPECT_LT(patches, open);
  }
}
