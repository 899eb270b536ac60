#include "vcg_ext/core/t_junctions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace vcgext {
namespace {

// The boundary vertices bucketed in a uniform grid (cells of about a mean boundary edge).
class VertexGrid {
 public:
  VertexGrid(const std::vector<Vec3>& V, const std::vector<int>& verts, double cell) : V_(V), cell_(cell) {
    for (int v : verts) cells_[Key(Cell(V[size_t(v)]))].push_back(v);
  }
  // Vertices within `tol` of the segment a-b (the cells around samples every half cell along it).
  void Near(const Vec3& a, const Vec3& b, std::vector<int>& out) const {
    out.clear();
    const int steps = 1 + int(std::ceil((b - a).norm() / (0.5 * cell_)));
    for (int i = 0; i <= steps; ++i) {
      const std::array<long, 3> c = Cell(a + (b - a) * (double(i) / steps));
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

 private:
  std::array<long, 3> Cell(const Vec3& p) const {
    return {long(std::floor(p[0] / cell_)), long(std::floor(p[1] / cell_)), long(std::floor(p[2] / cell_))};
  }
  static std::uint64_t Key(const std::array<long, 3>& c) {
    return (std::uint64_t(c[0] & 0x1FFFFF) << 42) | (std::uint64_t(c[1] & 0x1FFFFF) << 21) | std::uint64_t(c[2] & 0x1FFFFF);
  }
  const std::vector<Vec3>& V_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// A vertex of the polygon a face becomes: its index and the sides of the face it lies on (bit k:
// the side from corner k to corner k + 1; a corner lies on two).
struct PolyVertex {
  int v;
  unsigned sides;
};

// True when the vertices of `poly` other than poly[skip] all lie on one side of the face.
bool OnOneSide(const std::vector<PolyVertex>& poly, size_t skip) {
  unsigned common = 7;
  for (size_t i = 0; i < poly.size(); ++i)
    if (i != skip) common &= poly[i].sides;
  return common != 0;
}

// Triangulates the face's boundary polygon (its corners and the vertices inserted into its sides,
// counter-clockwise) by clipping ears: a vertex whose triangle with its two neighbours has area
// (the three are not on one side of the face) and whose removal leaves a polygon with area. The
// polygon's vertices lie on the face's boundary in order, so three of them are collinear exactly
// when they share a side: the test is combinatorial, not a floating-point orientation. False if no
// ear is found (cannot happen for a polygon with area; the face is then kept as it is).
bool ClipEars(std::vector<PolyVertex> poly, std::vector<Tri>& out) {
  while (poly.size() > 3) {
    bool clipped = false;
    for (size_t i = 0; i < poly.size() && !clipped; ++i) {
      const size_t p = (i + poly.size() - 1) % poly.size(), n = (i + 1) % poly.size();
      if (poly[p].sides & poly[i].sides & poly[n].sides) continue;  // collinear: no area
      if (OnOneSide(poly, i)) continue;                              // the rest would have none
      out.push_back({poly[p].v, poly[i].v, poly[n].v});
      poly.erase(poly.begin() + long(i));
      clipped = true;
    }
    if (!clipped) return false;
  }
  out.push_back({poly[0].v, poly[1].v, poly[2].v});
  return true;
}

}  // namespace

int CloseTJunctions(const std::vector<Vec3>& V, std::vector<Tri>& F, const std::vector<int>& boundarySides, double tol) {
  if (boundarySides.empty() || !(tol > 0) || !std::isfinite(tol)) return 0;
  std::vector<int> verts;
  double length = 0;
  for (int s : boundarySides) {
    const Tri& f = F[size_t(s / 3)];
    const int a = f[size_t(s % 3)], b = f[size_t((s % 3 + 1) % 3)];
    verts.push_back(a);
    verts.push_back(b);
    length += (V[size_t(b)] - V[size_t(a)]).norm();
  }
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  const VertexGrid grid(V, verts, std::max(length / double(boundarySides.size()), 4 * tol));

  // per face with inserted vertices: per side, (parameter along the side, vertex)
  std::unordered_map<int, std::array<std::vector<std::pair<double, int>>, 3>> hits;
  std::vector<int> near;
  int inserted = 0;
  for (int s : boundarySides) {
    const int fi = s / 3, k = s % 3;
    const Tri& f = F[size_t(fi)];
    const Vec3 &a = V[size_t(f[size_t(k)])], &b = V[size_t(f[size_t((k + 1) % 3)])];
    const double len2 = (b - a).squaredNorm();
    if (!(len2 > 4 * tol * tol)) continue;
    grid.Near(a, b, near);
    for (int v : near) {
      if (v == f[0] || v == f[1] || v == f[2]) continue;
      const double t = (V[size_t(v)] - a).dot(b - a) / len2;
      const double along = t * std::sqrt(len2);
      if (along <= tol || std::sqrt(len2) - along <= tol) continue;
      if ((V[size_t(v)] - (a + t * (b - a))).norm() > tol) continue;
      hits[fi][size_t(k)].push_back({t, v});
      ++inserted;
    }
  }
  if (hits.empty()) return 0;

  std::vector<int> split;
  for (const auto& h : hits) split.push_back(h.first);
  std::sort(split.begin(), split.end());  // the appended faces' order does not depend on hashing
  std::vector<char> drop(F.size(), 0);
  std::vector<Tri> pieces;
  for (int fi : split) {
    std::vector<PolyVertex> poly;
    for (unsigned k = 0; k < 3; ++k) {
      poly.push_back({F[size_t(fi)][k], (1u << k) | (1u << ((k + 2) % 3))});
      auto side = hits[fi][k];
      std::sort(side.begin(), side.end());
      for (const auto& th : side) poly.push_back({th.second, 1u << k});
    }
    std::vector<int> ids;
    for (const PolyVertex& p : poly) ids.push_back(p.v);
    std::sort(ids.begin(), ids.end());
    const bool repeats = std::adjacent_find(ids.begin(), ids.end()) != ids.end();  // a vertex near two sides
    const size_t before = pieces.size();
    if (!repeats && ClipEars(poly, pieces)) {
      drop[size_t(fi)] = 1;
    } else {
      pieces.resize(before);
      for (const auto& side : hits[fi]) inserted -= int(side.size());
    }
  }
  std::vector<Tri> out;
  out.reserve(F.size() + pieces.size());
  for (size_t i = 0; i < F.size(); ++i)
    if (!drop[i]) out.push_back(F[i]);
  out.insert(out.end(), pieces.begin(), pieces.end());
  F.swap(out);
  return inserted;
}

}  // namespace vcgext
