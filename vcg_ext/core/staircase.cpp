#include "vcg_ext/core/staircase.h"
#include "vcg_ext/core/edge_faces.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

namespace vcgext {
namespace {

constexpr int kRoundedFaces = 10, kVoxelLevels = 10;
constexpr double kRoundedFaceShare = 0.005, kStepEdges = 0.25;
constexpr double kVoxelAreaShare = 0.9, kVoxelStepEdgeShare = 0.2;
constexpr double kAxisCosine = 0.999;           // a triangle facing along an axis
const double kStepCosine = std::cos(M_PI / 3);  // two triangles turning by 60° or more

int CoincidentCornerFaces(const TriData& t) {
  int n = 0;
  for (const Tri& f : t.F)
    for (int k = 0; k < 3; ++k)
      if (f[k] != f[(k + 1) % 3] && t.V[size_t(f[k])] == t.V[size_t(f[(k + 1) % 3])]) { ++n; break; }
  return n;
}

double MedianEdge(const TriData& t) {
  std::vector<double> edges;
  for (const Tri& f : t.F)
    for (int k = 0; k < 3; ++k)
      if (const double l = (t.V[size_t(f[k])] - t.V[size_t(f[(k + 1) % 3])]).norm(); l > 0) edges.push_back(l);
  if (edges.empty()) return 0;
  std::nth_element(edges.begin(), edges.begin() + long(edges.size() / 2), edges.end());
  return edges[edges.size() / 2];
}

// The coordinates' step (see FindStaircase) and the fewest distinct values on an axis with two or
// more (0, 0 when no axis has).
std::pair<double, int> CoordinateStep(const std::vector<Vec3>& V) {
  double step = std::numeric_limits<double>::infinity();
  int levels = std::numeric_limits<int>::max();
  std::vector<double> x(V.size());
  std::vector<std::pair<double, size_t>> gaps;  // per distinct value: its gap, its vertices
  for (int a = 0; a < 3; ++a) {
    for (size_t i = 0; i < V.size(); ++i) x[i] = V[i][a];
    std::sort(x.begin(), x.end());
    gaps.clear();
    for (size_t i = 0, j; i < x.size(); i = j) {
      for (j = i; j < x.size() && x[j] == x[i]; ++j) {}
      double gap = j < x.size() ? x[j] - x[i] : std::numeric_limits<double>::infinity();
      if (i > 0) gap = std::min(gap, x[i] - x[i - 1]);
      gaps.push_back({gap, j - i});
    }
    if (gaps.size() < 2) continue;
    levels = std::min(levels, int(gaps.size()));
    std::sort(gaps.begin(), gaps.end());
    size_t seen = 0;
    for (const auto& [gap, count] : gaps)
      if ((seen += count) * 2 >= x.size()) { step = std::min(step, gap); break; }
  }
  return std::isfinite(step) ? std::make_pair(step, levels) : std::make_pair(0.0, 0);
}

// Area share of the triangles whose normal is within kAxisCosine of an axis.
double AxisAlignedShare(const TriData& t) {
  double aligned = 0, total = 0;
  for (const Tri& f : t.F) {
    const Vec3 n = (t.V[size_t(f[1])] - t.V[size_t(f[0])]).cross(t.V[size_t(f[2])] - t.V[size_t(f[0])]);
    const double l = n.norm();
    total += l;
    if (l > 0 && n.cwiseAbs().maxCoeff() >= kAxisCosine * l) aligned += l;
  }
  return total > 0 ? aligned / total : 0;
}

// Share of the edges between two triangles whose normals turn by 60° or more.
double StepEdgeShare(const TriData& t) {
  const EdgeFaces e = BuildEdgeFaces(t.F);
  const std::vector<Vec3> N = FaceNormals(t);
  long inner = 0, steps = 0;
  for (size_t id = 0; id + 1 < e.offs.size(); ++id) {
    const int b = e.offs[id];
    if (e.offs[id + 1] - b != 2) continue;
    ++inner;
    steps += N[size_t(e.idx[size_t(b)] / 3)].dot(N[size_t(e.idx[size_t(b) + 1] / 3)]) <= kStepCosine;
  }
  return inner > 0 ? double(steps) / double(inner) : 0;
}

}  // namespace

Staircase FindStaircase(const TriData& raw, const TriData& mesh) {
  Staircase s;
  s.coincidentFaces = CoincidentCornerFaces(raw);
  s.faces = int(raw.F.size());
  const bool cornersMeet =
      s.coincidentFaces >= kRoundedFaces && s.coincidentFaces >= kRoundedFaceShare * double(raw.F.size());
  s.axisAlignedShare = AxisAlignedShare(mesh);
  if (!cornersMeet && s.axisAlignedShare < kVoxelAreaShare) return s;
  s.diagonal = BBoxDiagonal(raw.V);
  s.medianEdge = MedianEdge(raw);
  int levels = 0;
  std::tie(s.step, levels) = CoordinateStep(raw.V);
  if (!(s.medianEdge > 0) || !(s.step >= kStepEdges * s.medianEdge)) return s;
  s.rounded = cornersMeet;
  if (s.axisAlignedShare >= kVoxelAreaShare && levels >= kVoxelLevels) {
    s.stepEdgeShare = StepEdgeShare(mesh);
    s.voxels = !s.rounded && s.stepEdgeShare >= kVoxelStepEdgeShare;
  }
  return s;
}

std::string StaircaseWarning(const Staircase& s) {
  if (!s.rounded && !s.voxels) return {};
  char buf[900];
  const char* advice =
      "Its steps are fitted as detail: far more patches, and a patch budget may not be reached. Smooth it "
      "first: Filters > Smoothing, Fairing and Deformation > Taubin Smooth (PyMeshLab: "
      "apply_coord_taubin_smoothing)";
  if (s.rounded)
    std::snprintf(buf, sizeof buf,
                  "%d triangles (%.2g %%) have two corners at the same position and the coordinates come in "
                  "steps of %.3g (%.2g times the median edge, %.2g %% of the diagonal): they were rounded (a file "
                  "written with too few digits), which makes the surface a staircase. %s, or export the scan with "
                  "more digits",
                  s.coincidentFaces, 100.0 * s.coincidentFaces / double(s.faces), s.step, s.step / s.medianEdge,
                  100 * s.step / s.diagonal, advice);
  else
    std::snprintf(buf, sizeof buf,
                  "the surface is made of axis-aligned voxel faces, the coordinates come in steps of %.3g (%.2g "
                  "times the median edge, %.2g %% of the diagonal) and %.0f %% of its edges are steps between "
                  "them: a voxel export (a segmentation mask, an occupancy grid), a staircase. %s",
                  s.step, s.step / s.medianEdge, 100 * s.step / s.diagonal, 100 * s.stepEdgeShare, advice);
  return buf;
}

}  // namespace vcgext
