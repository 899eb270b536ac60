// fit_and_bake.mlx end to end: a quad control mesh made by "another tool" (a cube-sphere OBJ
// written here) is fitted to a dense sphere; the fit must be close to the analytic sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "e2e_support.h"
#include "test_support.h"
#include "vcg_ext/fit/fit_io.h"
#include "vcg_ext/io/mesh_io.h"

namespace {

// Cube with n×n quads per side, projected to the unit sphere (counter-clockwise from outside).
vcgext::QuadData CubeSphere(int n) {
  vcgext::QuadData q;
  std::map<std::array<long, 3>, int> ids;
  auto vid = [&](const vcgext::Vec3& p) {
    std::array<long, 3> key{std::lround(p[0] * 1e6), std::lround(p[1] * 1e6), std::lround(p[2] * 1e6)};
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    q.V.push_back(p.normalized());
    return ids[key] = int(q.V.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int sgn = -1; sgn <= 1; sgn += 2) {
      vcgext::Vec3 nrm = vcgext::Vec3::Zero();
      nrm[axis] = sgn;
      vcgext::Vec3 a = vcgext::Vec3::Zero(), b = vcgext::Vec3::Zero();
      a[(axis + 1) % 3] = 1;
      b[(axis + 2) % 3] = 1;
      if (sgn < 0) std::swap(a, b);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          auto P = [&](int ii, int jj) { return vcgext::Vec3(nrm + a * (2.0 * ii / n - 1) + b * (2.0 * jj / n - 1)); };
          q.F.push_back({vid(P(i, j)), vid(P(i + 1, j)), vid(P(i + 1, j + 1)), vid(P(i, j + 1))});
        }
    }
  return q;
}

using e2e::JsonNumber;

TEST(MlxScripts, FitAndBakeFitsForeignQuadMeshToSphere) {
  const std::string dir = e2e::OutPath("fit_sphere");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  vcgext::TMesh ref;
  testsupport::ToVcg(testsupport::Icosphere(5), ref);  // 10242 vertices on the unit sphere
  ASSERT_EQ(vcgext::SaveMesh(dir + "/sphere.off", ref), "");
  auto cube = CubeSphere(4);  // 96 quads, 8 valence-3 vertices
  ASSERT_EQ(vcgext::WriteQuadPly(dir + "/control.ply", cube), "");  // MeshLab 2020.09 cannot read OBJ

  auto r = e2e::Meshlabserver("-i " + e2e::Q(dir + "/sphere.off") + " -i " + e2e::Q(dir + "/control.ply") +
                              " -o " + e2e::Q(dir + "/limit.ply") + " -l 3 -m vq vc -s " +
                              e2e::Q(e2e::Script("fit_and_bake.mlx")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  // Files land in <reference>_cc next to the reference.
  const std::string json = e2e::Slurp(dir + "/sphere_cc/report.json");
  ASSERT_FALSE(json.empty()) << r.output;
  EXPECT_EQ(JsonNumber(json, "patches"), 96);
  EXPECT_EQ(JsonNumber(json, "irregular_vertices"), 8);
  // A 96-patch Catmull-Clark surface approximates the sphere to well under 1‰ of the diagonal
  // (radial error of the cubic B-spline patches); a broken fit (e.g. no fit at all: the
  // control net's limit shrinks by ~3%) is far above that.
  EXPECT_LT(JsonNumber(json, "rms_limit_permille"), 1.0) << json;
  EXPECT_LT(JsonNumber(json, "unprojectable_pct"), 0.5) << json;
  for (const char* f : {"displacement.png", "displacement.json", "control.obj", "control.mtl"})
    EXPECT_TRUE(std::ifstream(dir + "/sphere_cc/" + f).good()) << f;
  // The limit layer (position 3) lies on the unit sphere; its quality is the signed distance.
  vcgext::TMesh lim;
  ASSERT_EQ(vcgext::LoadMesh(dir + "/limit.ply", lim), "");
  EXPECT_EQ(lim.vn, 96 * 8 * 8 + 2);  // welded 8×8 tessellation of a closed genus-0 mesh
  double worst = 0;
  for (const auto& v : lim.vert) {
    double rr = vcgext::Vec3(v.cP()[0], v.cP()[1], v.cP()[2]).norm();
    worst = std::max(worst, std::abs(rr - 1.0));
    EXPECT_LT(std::abs(v.cQ()), 0.01);
  }
  EXPECT_LT(worst, 0.01);
}

// Control net read back from control.obj ("v x y z", "f a/t b/t c/t d/t"): mean length of the
// uniform Laplacian (vertex minus the average of its edge neighbours), in model units.
double MeanCageLaplacian(const std::string& objPath) {
  std::ifstream in(objPath);
  std::vector<vcgext::Vec3> V;
  std::vector<std::set<int>> nb;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string tag;
    ss >> tag;
    if (tag == "v") {
      double x, y, z;
      ss >> x >> y >> z;
      V.emplace_back(x, y, z);
    } else if (tag == "f") {
      std::vector<int> f;
      std::string tok;
      while (ss >> tok) f.push_back(std::stoi(tok.substr(0, tok.find('/'))) - 1);
      nb.resize(V.size());
      for (size_t k = 0; k < f.size(); ++k) {
        nb[f[k]].insert(f[(k + 1) % f.size()]);
        nb[f[(k + 1) % f.size()]].insert(f[k]);
      }
    }
  }
  if (V.empty() || nb.size() != V.size()) return NAN;
  double sum = 0;
  for (size_t i = 0; i < V.size(); ++i) {
    vcgext::Vec3 avg = vcgext::Vec3::Zero();
    for (int j : nb[i]) avg += V[j];
    sum += (V[i] - avg / double(nb[i].size())).norm();
  }
  return sum / double(V.size());
}

// fit_and_bake.mlx with one parameter value replaced (the script lists every parameter).
std::string FitScriptWith(const std::string& dir, const std::string& name, const std::string& value) {
  std::string s = e2e::Slurp(e2e::Script("fit_and_bake.mlx"));
  std::regex re("value=\"[^\"]*\" name=\"" + name + "\"");
  EXPECT_TRUE(std::regex_search(s, re)) << name;
  s = std::regex_replace(s, re, "value=\"" + value + "\" name=\"" + name + "\"");
  const std::string path = dir + "/fit_" + name + "_" + value + ".mlx";
  std::ofstream(path) << s;
  return path;
}

// A bumpy sphere r = 1 + 0.05 sin(5x) sin(5y) sin(5z) (detail the fit chases) and a foreign
// cube-sphere control mesh in `dir`; fit_and_bake.mlx runs with `name` = `value` in its own
// sub-folder. Returns the output folder (report.json, control.obj, ...) or "" on failure.
std::string FitBumpySphereWith(const std::string& dir, const std::string& name, const std::string& value) {
  if (e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode != 0) return "";
  const std::string control = dir + "/control.ply";
  if (!std::ifstream(control) && vcgext::WriteQuadPly(control, CubeSphere(4)) != "") return "";
  vcgext::TMesh ref;
  testsupport::ToVcg(testsupport::Icosphere(5), ref);
  for (auto& v : ref.vert) {
    vcgext::Vec3 p(v.cP()[0], v.cP()[1], v.cP()[2]);
    double r = 1.0 + 0.05 * std::sin(5 * p[0]) * std::sin(5 * p[1]) * std::sin(5 * p[2]);
    v.P() = vcg::Point3f(float(r * p[0]), float(r * p[1]), float(r * p[2]));
  }
  const std::string sub = dir + "/" + name + "_" + value;
  if (e2e::Run("mkdir -p " + e2e::Q(sub)).exitCode != 0 || vcgext::SaveMesh(sub + "/bumpy.off", ref) != "") return "";
  auto r = e2e::Meshlabserver("-i " + e2e::Q(sub + "/bumpy.off") + " -i " + e2e::Q(control) + " -o " +
                              e2e::Q(sub + "/limit.ply") + " -l 3 -s " + e2e::Q(FitScriptWith(dir, name, value)));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  return r.exitCode == 0 ? sub + "/bumpy_cc" : "";
}

// "Control cage smoothing" (smoothWeight, docs/fit.md "Control cage"): a control-net Laplacian
// term trades limit error for a calmer net: the fit with the term off and on.
TEST(MlxScripts, FitAndBakeCageSmoothingCalmsTheControlMesh) {
  const std::string dir = e2e::OutPath("fit_smooth");
  double lap[2], rms[2];
  const char* weights[2] = {"0", "1"};
  for (int i = 0; i < 2; ++i) {
    const std::string out = FitBumpySphereWith(dir, "smoothWeight", weights[i]);
    ASSERT_FALSE(out.empty());
    const std::string json = e2e::Slurp(out + "/report.json");
    rms[i] = JsonNumber(json, "rms_limit_permille");
    lap[i] = MeanCageLaplacian(out + "/control.obj");
    ASSERT_TRUE(std::isfinite(rms[i]) && std::isfinite(lap[i])) << json;
  }
  // The penalized minimizer has a smaller penalty and a larger data error than the unpenalized
  // one (a property of adding a convex term); μ = 1 is strong, so both changes are clear.
  EXPECT_LT(lap[1], 0.9 * lap[0]) << lap[0] << " -> " << lap[1];
  EXPECT_GT(rms[1], rms[0]) << rms[0] << " -> " << rms[1];
}

// "Least-squares displacement" (fitDisplacement, docs/fit.md "Bake"): the same fit, the texels
// point-sampled (paper) or fitted; the report says which, and the fitted displaced surface is
// clearly closer to the reference while the limit is the same.
TEST(MlxScripts, FitAndBakeLeastSquaresDisplacementBeatsPointSamples) {
  const std::string dir = e2e::OutPath("fit_dfit");
  double disp[2], lim[2];
  const char* values[2] = {"false", "true"};
  for (int i = 0; i < 2; ++i) {
    const std::string out = FitBumpySphereWith(dir, "fitDisplacement", values[i]);
    ASSERT_FALSE(out.empty());
    const std::string json = e2e::Slurp(out + "/report.json");
    EXPECT_NE(json.find(std::string("\"displacement_fit\": ") + values[i]), std::string::npos) << json;
    disp[i] = JsonNumber(json, "rms_displaced_permille");
    lim[i] = JsonNumber(json, "rms_limit_permille");
  }
  EXPECT_DOUBLE_EQ(lim[0], lim[1]);
  EXPECT_LT(disp[1], 0.7 * disp[0]) << disp[0] << " -> " << disp[1];
}

// "Tile size per patch" (adaptiveTiles, docs/fit.md "Tile sizes") through meshlabserver: the
// report and the atlas sidecar say which layout was baked, the per-patch layout lists one tile
// per patch, and both spend about the same samples (the paper's budget).
TEST(MlxScripts, FitAndBakeTileSizePerPatch) {
  const std::string dir = e2e::OutPath("fit_tiles");
  double samples[2];
  const char* values[2] = {"false", "true"};
  for (int i = 0; i < 2; ++i) {
    const std::string out = FitBumpySphereWith(dir, "adaptiveTiles", values[i]);
    ASSERT_FALSE(out.empty());
    const std::string json = e2e::Slurp(out + "/report.json");
    const std::string atlas = e2e::Slurp(out + "/displacement.json");
    const std::string kind = i ? "adaptive" : "uniform";
    EXPECT_NE(json.find("\"texture_tiles\": \"" + kind + "\""), std::string::npos) << json;
    EXPECT_NE(atlas.find("\"tile_sizes\": \"" + kind + "\""), std::string::npos) << atlas;
    EXPECT_EQ(atlas.find("\"tiles\": ["), i ? atlas.find("\"tiles\": [") : std::string::npos);
    if (i) {  // one [x, y, size] per patch
      const size_t b = atlas.find("\"tiles\": [");
      ASSERT_NE(b, std::string::npos);
      const std::string list = atlas.substr(b, atlas.find("]],", b) - b);
      EXPECT_EQ(std::count(list.begin(), list.end(), '[') - 1, JsonNumber(json, "patches")) << list.substr(0, 200);
    }
    samples[i] = JsonNumber(json, "texture_samples");
    EXPECT_GT(samples[i], 0);
  }
  EXPECT_NEAR(samples[1], samples[0], 0.25 * samples[0]);
}

TEST(MlxScripts, FitAndBakeRejectsNegativeCageSmoothing) {
  const std::string dir = e2e::OutPath("fit_smooth_bad");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  vcgext::TMesh ref;
  testsupport::ToVcg(testsupport::Icosphere(3), ref);
  ASSERT_EQ(vcgext::SaveMesh(dir + "/sphere.off", ref), "");
  ASSERT_EQ(vcgext::WriteQuadPly(dir + "/control.ply", CubeSphere(2)), "");
  auto r = e2e::Meshlabserver("-i " + e2e::Q(dir + "/sphere.off") + " -i " + e2e::Q(dir + "/control.ply") +
                              " -o " + e2e::Q(dir + "/out.ply") + " -s " +
                              e2e::Q(FitScriptWith(dir, "smoothWeight", "-1")));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("control cage smoothing must be in [0, 10]"), std::string::npos) << r.output;
}

// CubeSphere(4) as a quad-dominant cage: on every side one quad split into two triangles and two
// neighbouring quads merged into a hexagon, written as a polygonal PLY (MeshLab fans the polygons
// with faux edges). Returns the number of polygon corners (one patch each once subdivided).
int WriteMixedCage(const std::string& path) {
  const auto q = CubeSphere(4);
  std::vector<std::vector<int>> faces;
  for (size_t f = 0; f < q.F.size(); ++f) {
    const auto& c = q.F[f];
    if (f % 16 == 0) {
      faces.push_back({c[0], c[1], c[2]});
      faces.push_back({c[0], c[2], c[3]});
    } else if (f % 16 == 5) {  // with the next quad of its row (b, e, f, c): the hexagon a b e f c d
      const auto& n = q.F[f + 1];
      faces.push_back({c[0], c[1], n[1], n[2], c[2], c[3]});
      ++f;
    } else {
      faces.push_back({c[0], c[1], c[2], c[3]});
    }
  }
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << q.V.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << faces.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  out.precision(17);
  for (const auto& v : q.V) out << v.x() << " " << v.y() << " " << v.z() << "\n";
  int corners = 0;
  for (const auto& f : faces) {
    out << f.size();
    for (int c : f) out << " " << c;
    out << "\n";
    corners += int(f.size());
  }
  return corners;
}

// A quad-dominant cage (triangles and hexagons among its quads) is subdivided once and fitted:
// one patch per polygon corner, as close to the sphere as the pure-quad cage's fit.
TEST(MlxScripts, FitAndBakeSubdividesAQuadDominantCageOnce) {
  const std::string dir = e2e::OutPath("fit_mixed");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  vcgext::TMesh ref;
  testsupport::ToVcg(testsupport::Icosphere(5), ref);
  ASSERT_EQ(vcgext::SaveMesh(dir + "/sphere.off", ref), "");
  const int corners = WriteMixedCage(dir + "/control.ply");
  ASSERT_EQ(corners, 384);  // per side 13 quads, 2 triangles, 1 hexagon: 52 + 6 + 6
  auto r = e2e::Meshlabserver("-i " + e2e::Q(dir + "/sphere.off") + " -i " + e2e::Q(dir + "/control.ply") +
                              " -o " + e2e::Q(dir + "/out.ply") + " -s " + e2e::Q(e2e::Script("fit_and_bake.mlx")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("the control layer has 12 triangles and 6 polygons of more than four sides among its 78 "
                          "quads: subdivided once by Catmull-Clark"),
            std::string::npos)
      << r.output;
  const std::string json = e2e::Slurp(dir + "/sphere_cc/report.json");
  ASSERT_FALSE(json.empty()) << r.output;
  EXPECT_EQ(JsonNumber(json, "patches"), corners);
  EXPECT_EQ(JsonNumber(json, "degenerate_patches"), 0);
  // The 96-quad cage fits to < 1 per mille (FitAndBakeFitsForeignQuadMeshToSphere); four times
  // the patches do at least as well. Unsubdivided (no fit) the limit lies ~3 % inside.
  EXPECT_LT(JsonNumber(json, "rms_limit_permille"), 1.0) << json;
  EXPECT_LT(JsonNumber(json, "unprojectable_pct"), 0.5) << json;
  // control.obj holds the fitted quads: 384 four-cornered faces.
  std::ifstream obj(dir + "/sphere_cc/control.obj");
  int quadFaces = 0, otherFaces = 0;
  for (std::string line; std::getline(obj, line);)
    if (line.rfind("f ", 0) == 0) {
      std::istringstream ls(line.substr(2));
      int n = 0;
      for (std::string tok; ls >> tok;) ++n;
      ++(n == 4 ? quadFaces : otherFaces);
    }
  EXPECT_EQ(quadFaces, corners);
  EXPECT_EQ(otherFaces, 0);
}

// A cage some of whose quads were stored reversed against their neighbours (an export, parts
// merged) is read oriented coherently, as most of its faces, and fits as the cage stored whole;
// it was refused ("edges join faces of inconsistent orientation").
TEST(MlxScripts, FitAndBakeOrientsQuadsStoredReversed) {
  const std::string dir = e2e::OutPath("fit_reversed");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir + "/whole") + " " + e2e::Q(dir + "/reversed")).exitCode, 0);
  vcgext::TMesh ref;
  testsupport::ToVcg(testsupport::Icosphere(5), ref);
  vcgext::QuadData cage = CubeSphere(4);
  std::string json[2];
  for (int reversed : {0, 1}) {
    const std::string sub = dir + (reversed ? "/reversed" : "/whole");
    ASSERT_EQ(vcgext::SaveMesh(sub + "/sphere.off", ref), "");
    if (reversed)
      for (int f : {3, 40, 77}) std::reverse(cage.F[f].begin(), cage.F[f].end());
    ASSERT_EQ(vcgext::WriteQuadPly(sub + "/control.ply", cage), "");
    auto r = e2e::Meshlabserver("-i " + e2e::Q(sub + "/sphere.off") + " -i " + e2e::Q(sub + "/control.ply") +
                                " -o " + e2e::Q(sub + "/out.ply") + " -s " + e2e::Q(e2e::Script("fit_and_bake.mlx")));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("stored reversed") != std::string::npos, reversed == 1) << r.output;
    if (reversed) {
      EXPECT_NE(r.output.find("6 of the control layer's triangles were stored reversed against their neighbours"),
                std::string::npos)
          << r.output;
    }
    json[reversed] = e2e::Slurp(sub + "/sphere_cc/report.json");
    ASSERT_FALSE(json[reversed].empty()) << r.output;
  }
  EXPECT_EQ(JsonNumber(json[1], "patches"), 96);
  EXPECT_EQ(JsonNumber(json[1], "irregular_vertices"), 8);
  // the same quads (a reversed quad read back may start at another corner: the fit can differ in
  // its last digits where it has not converged)
  EXPECT_NEAR(JsonNumber(json[1], "rms_limit_permille"), JsonNumber(json[0], "rms_limit_permille"),
              0.01 * JsonNumber(json[0], "rms_limit_permille"));
  EXPECT_LT(JsonNumber(json[1], "unprojectable_pct"), 0.5) << json[1];
}

// A control layer with a closed piece of two quads glued along all their edges (a pillow: what
// pairing a tetrahedron's triangles makes) beside a cube-sphere cage: its corners are doublets no
// merge removes and no Catmull-Clark surface has. The error says so in the user's terms and names
// the filter that deletes such pieces (it named the library's RemoveDoublets before).
TEST(MlxScripts, FitAndBakeRefusesAPillowInTheControlLayerSayingHowToDeleteIt) {
  const std::string dir = e2e::OutPath("fit_pillow");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  vcgext::TMesh ref;
  testsupport::ToVcg(testsupport::Icosphere(4), ref);
  ASSERT_EQ(vcgext::SaveMesh(dir + "/sphere.off", ref), "");
  vcgext::QuadData cage = CubeSphere(4);
  const int b = int(cage.V.size());
  for (int i = 0; i < 4; ++i) cage.V.push_back(vcgext::Vec3(3 + (i == 1 || i == 2), i >= 2, 0));
  cage.F.push_back({b, b + 1, b + 2, b + 3});
  cage.F.push_back({b + 3, b + 2, b + 1, b});
  ASSERT_EQ(vcgext::WriteQuadPly(dir + "/control.ply", cage), "");
  auto r = e2e::Meshlabserver("-i " + e2e::Q(dir + "/sphere.off") + " -i " + e2e::Q(dir + "/control.ply") +
                              " -o " + e2e::Q(dir + "/out.ply") + " -s " + e2e::Q(e2e::Script("fit_and_bake.mlx")));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("the control mesh has 4 interior vertices of valence 2 that no merge removes"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("Remove Isolated pieces (wrt Face Num.)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("vcgext::"), std::string::npos) << "no library names in a user's error: " << r.output;
  EXPECT_TRUE(e2e::Slurp(dir + "/sphere_cc/report.json").empty());
}

TEST(MlxScripts, FitAndBakeRejectsTriangleControlLayer) {
  const std::string dir = e2e::OutPath("fit_bad");
  ASSERT_EQ(e2e::Run("mkdir -p " + e2e::Q(dir)).exitCode, 0);
  vcgext::TMesh ref;
  testsupport::ToVcg(testsupport::Icosphere(3), ref);
  ASSERT_EQ(vcgext::SaveMesh(dir + "/a.off", ref), "");
  ASSERT_EQ(vcgext::SaveMesh(dir + "/b.off", ref), "");
  auto r = e2e::Meshlabserver("-i " + e2e::Q(dir + "/a.off") + " -i " + e2e::Q(dir + "/b.off") +
                              " -o " + e2e::Q(dir + "/out.ply") + " -s " + e2e::Q(e2e::Script("fit_and_bake.mlx")));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("not pure-quad"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("a layer of triangles only is no Catmull-Clark control mesh"), std::string::npos) << r.output;
}

}  // namespace
