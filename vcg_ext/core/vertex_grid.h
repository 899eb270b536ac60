#pragma once
/// \file vertex_grid.h
/// A uniform grid of some of a mesh's vertices (a hash map of cells): which vertices lie near a
/// point or a segment. For tolerance look-ups (the welds and T-junctions of the working copy,
/// input_prep.h), where the distances are far below the mesh's edges and a few cells are visited.
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

class VertexGrid {
 public:
  /// The vertices `verts` of `V` in cells of side `cell` (> 0, at least a 10^-12 of their bounding
  /// box's diagonal). Queries lie within their bounding box.
  VertexGrid(const std::vector<Vec3>& V, const std::vector<int>& verts, double cell);
  /// Every vertex of the grid within 3/4 `cell` of the segment a-b (a = b: within `cell` of the point), and some
  /// farther, each once in increasing order: the 27 cells around samples every half cell along it.
  void Near(const Vec3& a, const Vec3& b, std::vector<int>& out) const;

 private:
  std::array<long, 3> Cell(const Vec3& p) const;
  static std::uint64_t Key(const std::array<long, 3>& c);
  double cell_;
  Vec3 lo_;  // the grid's corner: the vertices' lowest coordinates
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

/// Each vertex of `verts` (increasing) merged into the first vertex of `verts` before it that is
/// kept (not merged itself), lies within `eps` and passes `allowed(u, kept)`. Returns each vertex's
/// representative (the identity outside `verts`); `welded`: how many were merged.
template <class Allowed>
std::vector<int> WeldWithin(const std::vector<Vec3>& V, const std::vector<int>& verts, double eps, Allowed allowed,
                            int* welded) {
  std::vector<int> into(V.size()), near;
  for (size_t v = 0; v < V.size(); ++v) into[v] = int(v);
  *welded = 0;
  const VertexGrid grid(V, verts, eps);
  for (int u : verts) {
    grid.Near(V[size_t(u)], V[size_t(u)], near);
    for (int k : near) {
      if (k >= u) break;
      if (into[size_t(k)] == k && (V[size_t(k)] - V[size_t(u)]).norm() <= eps && allowed(u, k)) {
        into[size_t(u)] = k;
        ++*welded;
        break;
      }
    }
  }
  return into;
}

}  // namespace vcgext
