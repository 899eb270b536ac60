#include "vcg_ext/core/seams.h"
#include "vcg_ext/core/vertex_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <unordered_map>
#include <utility>

namespace vcgext {
namespace {

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

// The ends of the boundary sides, sorted, once each.
std::vector<int> BoundaryVertices(const std::vector<Tri>& F, const std::vector<int>& boundarySides) {
  std::vector<int> verts;
  for (int s : boundarySides)
    for (int end = 0; end < 2; ++end) verts.push_back(F[size_t(s / 3)][size_t((s % 3 + end) % 3)]);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  return verts;
}

// The edges of the faces between two of the boundary vertices `verts` (sorted pairs): two such
// are sides of one surface already, never a seam's two copies.
std::set<std::pair<int, int>> EdgesBetween(size_t nV, const std::vector<Tri>& F, const std::vector<int>& verts) {
  std::vector<char> onBoundary(nV, 0);
  for (int v : verts) onBoundary[size_t(v)] = 1;
  std::set<std::pair<int, int>> edges;
  for (const Tri& f : F)
    for (int k = 0; k < 3; ++k)
      if (onBoundary[size_t(f[size_t(k)])] && onBoundary[size_t(f[size_t((k + 1) % 3)])])
        edges.insert(std::minmax(f[size_t(k)], f[size_t((k + 1) % 3)]));
  return edges;
}

}  // namespace

int WeldSeamVertices(const std::vector<Vec3>& V, const std::vector<Tri>& F, const std::vector<int>& boundarySides,
                     double tol, std::vector<int>& into) {
  into.resize(V.size());
  std::iota(into.begin(), into.end(), 0);
  if (boundarySides.empty() || !(tol > 0) || !std::isfinite(tol)) return 0;
  const std::vector<int> verts = BoundaryVertices(F, boundarySides);
  const std::set<std::pair<int, int>> edges = EdgesBetween(V.size(), F, verts);
  int welded = 0;
  into = WeldWithin(V, verts, tol, [&](int u, int v) { return !edges.count(std::minmax(u, v)); }, &welded);
  for (const Tri& f : F)  // two vertices of a face merged into one (a boundary edge under tol): none
    if (into[size_t(f[0])] == into[size_t(f[1])] || into[size_t(f[1])] == into[size_t(f[2])] ||
        into[size_t(f[0])] == into[size_t(f[2])]) {
      std::iota(into.begin(), into.end(), 0);
      return 0;
    }
  return welded;
}

int NearBoundaryVertices(const std::vector<Vec3>& V, const std::vector<Tri>& F, const std::vector<int>& boundarySides,
                         double share, double& reach, double& widest) {
  widest = reach = 0;
  if (boundarySides.empty() || !(share > 0)) return 0;
  // each boundary vertex's shortest boundary side, and the median side
  std::vector<double> shortest(V.size(), std::numeric_limits<double>::infinity()), sides;
  for (int s : boundarySides) {
    const int a = F[size_t(s / 3)][size_t(s % 3)], b = F[size_t(s / 3)][size_t((s % 3 + 1) % 3)];
    const double len = (V[size_t(a)] - V[size_t(b)]).norm();
    shortest[size_t(a)] = std::min(shortest[size_t(a)], len);
    shortest[size_t(b)] = std::min(shortest[size_t(b)], len);
    sides.push_back(len);
  }
  std::nth_element(sides.begin(), sides.begin() + long(sides.size() / 2), sides.end());
  reach = share * sides[sides.size() / 2];
  const std::vector<int> verts = BoundaryVertices(F, boundarySides);
  Vec3 lo = V[size_t(verts[0])], hi = lo;
  for (int v : verts) {
    lo = lo.cwiseMin(V[size_t(v)]);
    hi = hi.cwiseMax(V[size_t(v)]);
  }
  // gaps this far below the boundary's extent are the seam weld's (a millionth of the diagonal),
  // and the grid's cells must not be (VertexGrid)
  if (!(reach > 1e-9 * (hi - lo).norm()) || !std::isfinite(reach)) {
    reach = 0;
    return 0;
  }
  const std::set<std::pair<int, int>> edges = EdgesBetween(V.size(), F, verts);
  const VertexGrid grid(V, verts, reach);
  std::vector<int> near;
  int count = 0;
  for (int u : verts) {
    grid.Near(V[size_t(u)], V[size_t(u)], near);
    double nearest = -1;
    for (int k : near) {
      const double d = (V[size_t(k)] - V[size_t(u)]).norm();
      if (d > 0 && d <= reach && d <= share * std::min(shortest[size_t(u)], shortest[size_t(k)]) &&
          !edges.count(std::minmax(u, k)) && (nearest < 0 || d < nearest))
        nearest = d;
    }
    if (nearest < 0) continue;
    ++count;
    widest = std::max(widest, nearest);
  }
  return count;
}

int CloseTJunctions(const std::vector<Vec3>& V, std::vector<Tri>& F, const std::vector<int>& boundarySides, double tol) {
  if (boundarySides.empty() || !(tol > 0) || !std::isfinite(tol)) return 0;
  double length = 0;
  for (int s : boundarySides)
    length += (V[size_t(F[size_t(s / 3)][size_t((s % 3 + 1) % 3)])] - V[size_t(F[size_t(s / 3)][size_t(s % 3)])]).norm();
  const std::vector<int> verts = BoundaryVertices(F, boundarySides);
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
