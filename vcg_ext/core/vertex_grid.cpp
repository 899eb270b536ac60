#include "vcg_ext/core/vertex_grid.h"

#include <algorithm>
#include <cmath>

namespace vcgext {

VertexGrid::VertexGrid(const std::vector<Vec3>& V, const std::vector<int>& verts, double cell)
    : cell_(cell), lo_(Vec3::Zero()) {
  if (!verts.empty()) lo_ = V[size_t(verts[0])];
  for (int v : verts) lo_ = lo_.cwiseMin(V[size_t(v)]);
  for (int v : verts) cells_[Key(Cell(V[size_t(v)]))].push_back(v);
}

void VertexGrid::Near(const Vec3& a, const Vec3& b, std::vector<int>& out) const {
  out.clear();
  const int steps = int(std::ceil((b - a).norm() / (0.5 * cell_)));
  for (int i = 0; i <= steps; ++i) {
    const std::array<long, 3> c = Cell(steps ? Vec3(a + (b - a) * (double(i) / steps)) : a);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
        }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::array<long, 3> VertexGrid::Cell(const Vec3& p) const {
  const Vec3 c = (p - lo_) / cell_;  // from the grid's corner: no overflow for far-off coordinates
  return {long(std::floor(c[0])), long(std::floor(c[1])), long(std::floor(c[2]))};
}

std::uint64_t VertexGrid::Key(const std::array<long, 3>& c) {
  return (std::uint64_t(c[0] & 0x1FFFFF) << 42) | (std::uint64_t(c[1] & 0x1FFFFF) << 21) | std::uint64_t(c[2] & 0x1FFFFF);
}

}  // namespace vcgext
