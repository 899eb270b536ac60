// A layer with a transformation matrix through meshlabserver (MeshLab 2020.09's interface; the
// PyMeshLab side: tests/python/test_layer_matrix.py): a matrix that is not a similarity is warned
// about, a rotation times one scale is not (docs/robustness.md "Layer matrices").
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "e2e_support.h"
#include "test_support.h"

namespace {

// fitmaps.mlx preceded by MeshLab's "Transform: Scale, Normalize" by (sx, sy, sz) about the
// origin, its matrix not frozen.
std::string ScaledFitmapsScript(const std::string& name, const char* sx, const char* sy, const char* sz) {
  std::string s = e2e::Slurp(e2e::Script("fitmaps.mlx"));
  const std::string scale = std::string(" <filter name=\"Transform: Scale, Normalize\">\n") +
                            "  <Param type=\"RichFloat\" value=\"" + sx + "\" name=\"axisX\"/>\n" +
                            "  <Param type=\"RichFloat\" value=\"" + sy + "\" name=\"axisY\"/>\n" +
                            "  <Param type=\"RichFloat\" value=\"" + sz + "\" name=\"axisZ\"/>\n" +
                            "  <Param type=\"RichBool\" value=\"false\" name=\"uniformFlag\"/>\n" +
                            "  <Param type=\"RichEnum\" value=\"0\" name=\"scaleCenter\" enum_cardinality=\"3\" "
                            "enum_val0=\"origin\" enum_val1=\"barycenter\" enum_val2=\"custom point\"/>\n" +
                            "  <Param type=\"RichPoint3f\" x=\"0\" y=\"0\" z=\"0\" name=\"customCenter\"/>\n" +
                            "  <Param type=\"RichBool\" value=\"false\" name=\"unitFlag\"/>\n" +
                            "  <Param type=\"RichBool\" value=\"false\" name=\"Freeze\"/>\n" +
                            "  <Param type=\"RichBool\" value=\"false\" name=\"allLayers\"/>\n" + " </filter>\n";
  s = std::regex_replace(s, std::regex("<FilterScript>\n"), "<FilterScript>\n" + scale);
  const std::string path = e2e::OutPath(name);
  std::ofstream(path) << s;
  return path;
}

e2e::RunResult RunScaled(const std::string& name, const char* sx, const char* sy, const char* sz) {
  return e2e::Meshlabserver("-i " + e2e::Q(testsupport::SamplePath("fandisk.off")) + " -o " +
                            e2e::Q(e2e::OutPath(name + ".ply")) + " -s " +
                            e2e::Q(ScaledFitmapsScript(name + ".mlx", sx, sy, sz)));
}

TEST(LayerMatrix, UnevenScaleIsWarnedAndASimilarityIsNot) {
  const auto uneven = RunScaled("matrix_uneven", "2", "1", "1");
  ASSERT_EQ(uneven.exitCode, 0) << uneven.output;
  EXPECT_NE(uneven.output.find("Warning: Compute Fitmaps: layer 'fandisk.off' has a transformation matrix that "
                               "scales unevenly"),
            std::string::npos)
      << uneven.output;
  const auto even = RunScaled("matrix_even", "3", "3", "3");
  ASSERT_EQ(even.exitCode, 0) << even.output;
  EXPECT_NE(even.output.find("Compute Fitmaps (fast mode)"), std::string::npos) << even.output;
  EXPECT_EQ(even.output.find("transformation matrix"), std::string::npos) << even.output;
}

}  // namespace
