#pragma once
/// \file quality.h
/// Display helpers shared by the filters: copy a named per-vertex attribute into the vertex
/// quality, and colour it with vcglib's red-to-blue quality ramp clamped to percentiles (so a
/// few outliers do not flatten the colour map).
#include <vcg/complex/algorithms/update/color.h>
#include <vcg/complex/complex.h>

#include <algorithm>
#include <string>
#include <vector>

namespace vcgext {

/// Copies the per-vertex float attribute `name` into v.Q(). Returns false if it does not exist.
template <class MeshType>
bool QualityFromAttribute(MeshType& m, const std::string& name) {
  if (!vcg::tri::Allocator<MeshType>::template IsValidHandle<float>(
          m, vcg::tri::Allocator<MeshType>::template FindPerVertexAttribute<float>(m, name)))
    return false;
  auto h = vcg::tri::Allocator<MeshType>::template FindPerVertexAttribute<float>(m, name);
  for (auto& v : m.vert)
    if (!v.IsD()) v.Q() = typename MeshType::VertexType::QualityType(h[v]);
  return true;
}

/// The [loPct, hiPct] percentiles of the vertex quality (live vertices).
template <class MeshType>
std::pair<double, double> QualityPercentiles(const MeshType& m, double loPct, double hiPct) {
  std::vector<double> q;
  q.reserve(m.vert.size());
  for (const auto& v : m.vert)
    if (!v.IsD()) q.push_back(double(v.cQ()));
  if (q.empty()) return {0.0, 0.0};
  auto at = [&](double pct) {
    size_t k = size_t(std::clamp(pct, 0.0, 100.0) / 100.0 * double(q.size() - 1) + 0.5);
    std::nth_element(q.begin(), q.begin() + k, q.end());
    return q[k];
  };
  double lo = at(loPct), hi = at(hiPct);
  return {lo, hi};
}

/// Colours vertices by quality with vcglib's ramp between the given percentiles.
/// Returns the (min, max) quality values that the ramp's ends stand for.
template <class MeshType>
std::pair<double, double> ColorizeQuality(MeshType& m, double loPct = 1.0, double hiPct = 99.0) {
  auto r = QualityPercentiles(m, loPct, hiPct);
  if (r.second <= r.first) r.second = r.first + 1e-12;
  vcg::tri::UpdateColor<MeshType>::PerVertexQualityRamp(m, typename MeshType::ScalarType(r.first),
                                                         typename MeshType::ScalarType(r.second));
  return r;
}

/// Colours the vertex quality with the ramp over a given range [lo, hi] (e.g. another layer's,
/// so that two layers' colours compare).
template <class MeshType>
void ColorizeQualityRange(MeshType& m, double lo, double hi) {
  if (hi <= lo) hi = lo + 1e-12;
  vcg::tri::UpdateColor<MeshType>::PerVertexQualityRamp(m, typename MeshType::ScalarType(lo),
                                                         typename MeshType::ScalarType(hi));
}

}  // namespace vcgext
