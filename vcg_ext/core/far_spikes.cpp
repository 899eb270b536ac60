/// \file far_spikes.cpp
/// Vertices flung far from the surface (far_spikes.h).
#include "vcg_ext/core/far_spikes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace vcgext {

FarSpikes FindFarSpikes(const TriData& m) {
  FarSpikes s;
  if (m.F.empty()) return s;  // (a mesh of zero size has a zero median edge: no spikes below)
  const size_t n = m.V.size();
  // the median edge from every stride-th face's three edges (an interior edge counts twice: the
  // same median), at most ~300k of them on a dense scan
  const size_t stride = std::max<size_t>(1, m.F.size() / 100000);
  std::vector<double> edges;
  edges.reserve(3 * (m.F.size() / stride + 1));
  std::vector<double> shortest(n, std::numeric_limits<double>::infinity()), opposite(n, 0.0);
  for (size_t i = 0; i < m.F.size(); ++i) {
    const Tri& f = m.F[i];
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      const double ab = (m.V[b] - m.V[a]).norm();
      if (i % stride == 0) edges.push_back(ab);
      shortest[a] = std::min(shortest[a], ab);
      shortest[b] = std::min(shortest[b], ab);
      opposite[c] = std::max(opposite[c], ab);  // c's opposite edge in this face
    }
  }
  const auto mid = edges.begin() + long(edges.size() / 2);
  std::nth_element(edges.begin(), mid, edges.end());
  const double median = *mid;
  if (!(median > 0)) return s;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo, loAll = lo, hiAll = hi;
  for (size_t v = 0; v < n; ++v) {
    if (!std::isfinite(shortest[v])) continue;  // in no face
    loAll = loAll.cwiseMin(m.V[v]);
    hiAll = hiAll.cwiseMax(m.V[v]);
    if (shortest[v] > kSpikeEdgeFactor * median && opposite[v] <= kSpikeNeedleShare * shortest[v]) {
      if (s.first < 0) s.first = int(v);
      ++s.count;
      s.edgeFactor = std::max(s.edgeFactor, shortest[v] / median);
      s.shortestEdge = s.count == 1 ? shortest[v] : std::min(s.shortestEdge, shortest[v]);
    } else {
      lo = lo.cwiseMin(m.V[v]);
      hi = hi.cwiseMax(m.V[v]);
    }
  }
  s.diag = (hiAll - loAll).norm();  // of the vertices in faces
  s.diagWithout = (hi.array() >= lo.array()).all() ? (hi - lo).norm() : 0.0;
  return s;
}

std::string FarSpikesError(const TriData& m, const std::vector<int>* vertexOf) {
  const FarSpikes s = FindFarSpikes(m);
  if (s.count == 0 || !(s.diagWithout > 0) || !(s.diag > kSpikeBoxFactor * s.diagWithout)) return "";
  const int first = vertexOf && s.first < int(vertexOf->size()) ? (*vertexOf)[size_t(s.first)] : s.first;
  char buf[900];
  std::snprintf(buf, sizeof buf,
                "%d %s far from the rest of the surface (first: vertex %d), at the tip of needle triangles up to "
                "%.3g times longer than the median edge (a scanner's wild points): with %s the bounding box is "
                "%.3g times the model's, and the Fitmaps, the fit and every error are measured against that box. "
                "Remove %s first: Filters > Selection > Select Faces with edges longer than... (%.3g: half "
                "the shortest edge at %s), then Filters > Selection > Delete Selected Faces and Vertices (PyMeshLab: "
                "compute_selection_by_edge_length, meshing_remove_selected_vertices_and_faces)",
                s.count, s.count == 1 ? "vertex lies" : "vertices lie", first, s.edgeFactor,
                s.count == 1 ? "it" : "them", s.diag / s.diagWithout, s.count == 1 ? "it" : "them",
                0.5 * s.shortestEdge, s.count == 1 ? "it" : "them");
  return buf;
}

void RefuseFarSpikes(WorkingCopy& w) {
  if (w.error.empty()) w.error = FarSpikesError(w.mesh, &w.meshToLive);
}

}  // namespace vcgext
