// A layer with a transformation matrix through meshlabserver (MeshLab 2020.09's interface; the
// PyMeshLab side: tests/python/test_layer_matrix.py): the quads layer carries the input's matrix;
// a matrix that is not a similarity is warned about, a rotation times one scale is not
// (docs/robustness.md "Layer matrices").
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include "e2e_support.h"
#include "test_support.h"

namespace {

// fitmaps.mlx preceded by MeshLab's "Transform: Scale, Normalize" by (sx, sy, sz) about the
// origin, its matrix not frozen.
std::string ScaledFitmapsScript(const std::string& name, const char* sx, const char* sy, const char* sz) {
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
  return e2e::ScriptWithFirstFilter("fitmaps.mlx", scale, name);
}

// quad_simplification.mlx preceded by MeshLab's "Transform: Translate, Center, set Origin" by
// (0.5, 0, 0), its matrix not frozen.
std::string TranslatedQuadsScript(const std::string& name) {
  const std::string move =
      " <filter name=\"Transform: Translate, Center, set Origin\">\n"
      "  <Param type=\"RichEnum\" value=\"0\" name=\"traslMethod\" enum_cardinality=\"3\" enum_val0=\"XYZ translation\" "
      "enum_val1=\"Center on BBox\" enum_val2=\"Set new Origin\"/>\n"
      "  <Param type=\"RichDynamicFloat\" value=\"0.5\" min=\"-10\" max=\"10\" name=\"axisX\"/>\n"
      "  <Param type=\"RichDynamicFloat\" value=\"0\" min=\"-10\" max=\"10\" name=\"axisY\"/>\n"
      "  <Param type=\"RichDynamicFloat\" value=\"0\" min=\"-10\" max=\"10\" name=\"axisZ\"/>\n"
      "  <Param type=\"RichPoint3f\" x=\"0\" y=\"0\" z=\"0\" name=\"newOrigin\"/>\n"
      "  <Param type=\"RichBool\" value=\"false\" name=\"Freeze\"/>\n"
      "  <Param type=\"RichBool\" value=\"false\" name=\"allLayers\"/>\n"
      " </filter>\n";
  return e2e::ScriptWithFirstFilter("quad_simplification.mlx", move, name);
}

// The 16 numbers of every <MLMatrix44> of a MeshLab project file, in order.
std::vector<std::vector<double>> ProjectMatrices(const std::string& mlp) {
  std::vector<std::vector<double>> out;
  const std::string text = e2e::Slurp(mlp);
  const std::regex block("<MLMatrix44>([^<]*)</MLMatrix44>");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), block); it != std::sregex_iterator(); ++it) {
    std::istringstream in((*it)[1].str());
    std::vector<double> m;
    double x;
    while (in >> x) m.push_back(x);
    out.push_back(m);
  }
  return out;
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

// The quads layer shows where the scan shows: meshlabserver's project (-w) gives both layers the
// translation (before: the quads layer had the identity). The input is copied first: -w writes
// every layer's mesh next to its file.
TEST(LayerMatrix, QuadsLayerCarriesTheInputsMatrix) {
  const std::string dir = e2e::OutPath("matrix_quads");
  ASSERT_EQ(e2e::Run("rm -rf " + e2e::Q(dir) + " && mkdir -p " + e2e::Q(dir) + " && cp " +
                     e2e::Q(testsupport::SamplePath("fandisk.off")) + " " + e2e::Q(dir + "/fandisk.off"))
                .exitCode,
            0);
  const auto r = e2e::Meshlabserver("-i " + e2e::Q(dir + "/fandisk.off") + " -s " +
                                    e2e::Q(TranslatedQuadsScript("matrix_quads.mlx")) + " -w " +
                                    e2e::Q(dir + "/project.mlp"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto m = ProjectMatrices(dir + "/project.mlp");
  ASSERT_EQ(m.size(), 2u) << e2e::Slurp(dir + "/project.mlp");
  const std::vector<double> moved = {1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_EQ(m[0], moved);  // the scan, as the Translate filter left it
  EXPECT_EQ(m[1], moved);  // its quads
}

}  // namespace
