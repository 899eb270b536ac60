// Staircase surfaces (staircase.h, docs/robustness.md "Rounded coordinates and voxel faces"):
// coordinates rounded to a coarse step and voxel-face exports are warned about with their step;
// fine rounding, collapsed edges, gridded CAD boxes and small voxel blocks are not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <tuple>

#include "test_support.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/staircase.h"

using vcgext::TriData;
using vcgext::Vec3;
using vcgext::WorkingCopy;

namespace {
double MedianEdge(const TriData& t) {
  std::vector<double> l;
  for (const auto& f : t.F)
    for (int k = 0; k < 3; ++k) l.push_back((t.V[f[k]] - t.V[f[(k + 1) % 3]]).norm());
  std::nth_element(l.begin(), l.begin() + long(l.size() / 2), l.end());
  return l[l.size() / 2];
}
TriData Rounded(TriData t, double h) {
  for (auto& p : t.V)
    for (int k = 0; k < 3; ++k) p[k] = h * std::round(p[k] / h);
  return t;
}
// The step the staircase warning of the layer's working copy gives, or -1 when there is none.
double WarnedStep(const TriData& t) {
  const WorkingCopy w = vcgext::PrepareWorkingCopy(t);
  EXPECT_EQ(w.error, "");
  for (const std::string& s : w.warnings)
    if (const size_t at = s.find("coordinates come in steps of "); at != std::string::npos)
      return std::stod(s.substr(at + std::strlen("coordinates come in steps of ")));
  return -1;
}
// The boundary faces of the unit voxels (integer corners) for which `inside` holds, in [-n, n)^3,
// two triangles per face, outward.
TriData VoxelFaces(int n, const std::function<bool(int, int, int)>& inside) {
  TriData t;
  std::map<std::tuple<int, int, int>, int> id;
  auto vertex = [&](int x, int y, int z) {
    const auto [it, fresh] = id.emplace(std::make_tuple(x, y, z), int(t.V.size()));
    if (fresh) t.V.push_back(Vec3(x, y, z));
    return it->second;
  };
  const int dir[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int quad[6][4][3] = {
      {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}};
  for (int i = -n; i < n; ++i)
    for (int j = -n; j < n; ++j)
      for (int k = -n; k < n; ++k) {
        if (!inside(i, j, k)) continue;
        for (int d = 0; d < 6; ++d) {
          if (inside(i + dir[d][0], j + dir[d][1], k + dir[d][2])) continue;
          int v[4];
          for (int c = 0; c < 4; ++c) v[c] = vertex(i + quad[d][c][0], j + quad[d][c][1], k + quad[d][c][2]);
          t.F.push_back({v[0], v[1], v[2]});
          t.F.push_back({v[0], v[2], v[3]});
        }
      }
  return t;
}
}  // namespace

TEST(Staircase, CoarselyRoundedCoordinatesAreWarnedAboutWithTheirStep) {
  const TriData sphere = testsupport::Icosphere(4);
  const double edge = MedianEdge(sphere);
  EXPECT_NEAR(WarnedStep(Rounded(sphere, edge)), edge, 1e-3 * edge);  // printed to 3 digits
  EXPECT_EQ(WarnedStep(Rounded(sphere, edge / 20)), -1);               // no corners meet
  TriData collapsed = sphere;  // one endpoint of every 30th face's first edge moved onto the other
  for (size_t f = 0; f < collapsed.F.size(); f += 30) collapsed.V[collapsed.F[f][1]] = collapsed.V[collapsed.F[f][0]];
  EXPECT_EQ(WarnedStep(collapsed), -1);  // corners meet, but the step is 10^-3 edges
  EXPECT_EQ(WarnedStep(testsupport::PlaneGrid(20, 20)), -1);  // a grid of its edge, no corners meeting
  const TriData rounded = Rounded(sphere, edge);
  const vcgext::Staircase s = vcgext::FindStaircase(rounded, vcgext::PrepareWorkingCopy(rounded).mesh);
  EXPECT_TRUE(s.rounded && !s.voxels);
  EXPECT_NEAR(s.StepEdges(), 1.0, 0.05);
}

TEST(Staircase, VoxelFacesAreWarnedAboutButNotGriddedBoxesOrSmallBlocks) {
  // an ellipsoid of unit voxels 30 across: every edge between two faces is a step or flat
  const TriData voxels = VoxelFaces(16, [](int i, int j, int k) {
    return (i + 0.5) * (i + 0.5) + (j + 0.5) * (j + 0.5) + 1.7 * (k + 0.5) * (k + 0.5) <= 15 * 15;
  });
  const WorkingCopy w = vcgext::PrepareWorkingCopy(voxels);
  const vcgext::Staircase s = vcgext::FindStaircase(voxels, w.mesh);
  EXPECT_TRUE(s.voxels && !s.rounded);
  EXPECT_DOUBLE_EQ(s.step, 1.0);
  EXPECT_DOUBLE_EQ(s.axisAlignedShare, 1.0);
  EXPECT_GT(s.stepEdgeShare, 0.2);
  EXPECT_LT(s.stepEdgeShare, 0.6);
  EXPECT_DOUBLE_EQ(WarnedStep(voxels), 1.0);
  // a box of 12 x 12 x 12 voxels: the same faces and step, but steps only along its 12 edges
  auto box = [](int i, int j, int k) {
    return std::max({std::abs(i + 0.5), std::abs(j + 0.5), std::abs(k + 0.5)}) < 6;
  };
  EXPECT_EQ(WarnedStep(VoxelFaces(6, box)), -1);
  // a blocky cross of 3 x 3 x 3 voxels: all steps, but 4 coordinate values per axis
  auto cross = [](int i, int j, int k) {
    return (i == 0) + (j == 0) + (k == 0) >= 2 && std::max({std::abs(i), std::abs(j), std::abs(k)}) <= 1;
  };
  EXPECT_EQ(WarnedStep(VoxelFaces(2, cross)), -1);
  // the ellipsoid's voxels rotated off the axes: not voxel faces along the axes
  TriData turned = voxels;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (auto& p : turned.V) p = R * p;
  EXPECT_EQ(WarnedStep(turned), -1);
}
