#include "vcg_ext/fit/texel_space.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

namespace vcgext {
namespace fitdetail {

void SidePoint(int e, int p, int den, int* i, int* j) {
  switch (e) {
    case 0: *i = p; *j = 0; break;
    case 1: *i = den; *j = p; break;
    case 2: *i = den - p; *j = den; break;
    default: *i = 0; *j = den - p; break;
  }
}

TileCell CellAt(const Eigen::Vector2d& uv, int T) {
  const double x = std::clamp(uv[0], 0.0, 1.0) * T, y = std::clamp(uv[1], 0.0, 1.0) * T;
  TileCell c;
  c.i = std::min(int(x), T - 1);
  c.j = std::min(int(y), T - 1);
  const double fx = x - c.i, fy = y - c.j;
  c.w[0] = (1 - fx) * (1 - fy);
  c.w[1] = fx * (1 - fy);
  c.w[2] = (1 - fx) * fy;
  c.w[3] = fx * fy;
  return c;
}


void Quantize(DisplacementAtlas& a) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int f = 0; f < a.Patches(); ++f)
    for (int j = 0; j < a.tileR[f]; ++j)
      for (int i = 0; i < a.tileR[f]; ++i) {
        double d = a.disp[a.Pixel(f, i, j)];
        lo = std::min(lo, d);
        hi = std::max(hi, d);
      }
  a.offset = lo;
  a.scale = hi > lo ? (hi - lo) / 65535.0 : 0.0;
  a.q16.assign(a.disp.size(), 0);
  for (size_t k = 0; k < a.disp.size(); ++k)
    if (a.scale > 0)
      a.q16[k] = std::uint16_t(std::clamp(std::lround((a.disp[k] - lo) / a.scale), 0L, 65535L));
}


TexelSpace::TexelSpace(const LimitSurface& ls, const DisplacementAtlas& a) : a_(a) {
  const int nF = ls.NumFaces();
  std::unordered_map<std::uint64_t, std::pair<int, int>> edge;  // key -> (intervals, first knot id)
  for (int f = 0; f < nF; ++f)
    for (int e = 0; e < 4; ++e) {
      const int x = ls.FaceVertex(f, e), y = ls.FaceVertex(f, (e + 1) % 4);
      auto it = edge.emplace(x < y ? EdgeKey(x, y) : EdgeKey(y, x), std::make_pair(a.tileR[f] - 1, -1)).first;
      it->second.first = std::min(it->second.first, a.tileR[f] - 1);
    }
  std::vector<int> corner(ls.NumVertices(), -1);
  offset_.resize(nF + 1, 0);
  for (int f = 0; f < nF; ++f) offset_[f + 1] = offset_[f] + a.tileR[f] * a.tileR[f];
  terms_.resize(offset_[nF]);
  int next = 0;
  for (int f = 0; f < nF; ++f) {
    const int T = a.tileR[f] - 1;
    int cv[4];
    for (int c = 0; c < 4; ++c) {
      cv[c] = ls.FaceVertex(f, c);
      if (corner[cv[c]] < 0) corner[cv[c]] = next++;
    }
    const int cu[4] = {0, T, T, 0}, cvv[4] = {0, 0, T, T};
    for (int c = 0; c < 4; ++c) terms_[offset_[f] + cvv[c] * (T + 1) + cu[c]] = {{corner[cv[c]], 0}, {1, 0}, 1};
    for (int e = 0; e < 4; ++e) {
      const int x = cv[e], y = cv[(e + 1) % 4];
      const bool fwd = x < y;
      auto& ed = edge[fwd ? EdgeKey(x, y) : EdgeKey(y, x)];
      const int Te = ed.first, k = T / Te;  // powers of two: Te divides T
      if (ed.second < 0) {
        ed.second = next;
        next += Te - 1;
      }
      // knot q (0..Te) of the canonical direction: a corner or an edge unknown
      auto knot = [&](int q) {
        if (q == 0) return corner[std::min(x, y)];
        if (q == Te) return corner[std::max(x, y)];
        return ed.second + q - 1;
      };
      for (int m = 1; m < T; ++m) {
        const int c = fwd ? m : T - m;  // canonical position, units 1/T
        int i = 0, j = 0;
        SidePoint(e, m, T, &i, &j);
        Term& t = terms_[offset_[f] + j * (T + 1) + i];
        if (c % k == 0) {
          t = {{knot(c / k), 0}, {1, 0}, 1};
        } else {
          const double w = double(c % k) / k;
          t = {{knot(c / k), knot(c / k + 1)}, {1 - w, w}, 2};
        }
      }
    }
    for (int j = 1; j < T; ++j)
      for (int i = 1; i < T; ++i) terms_[offset_[f] + j * (T + 1) + i] = {{next++, 0}, {1, 0}, 1};
  }
  n_ = next;
}

bool LayoutOk(const DisplacementAtlas& a, int nF) {
  if (a.Patches() != nF || int(a.tileX.size()) != nF || int(a.tileY.size()) != nF || a.width < 1 || a.height < 1 ||
      a.disp.size() != size_t(a.width) * a.height)
    return false;
  bool uniform = true;
  for (int f = 0; f < nF; ++f) {
    const int r = a.tileR[f];
    if (r < 2 || a.tileX[f] < 0 || a.tileY[f] < 0 || a.tileX[f] + r > a.width || a.tileY[f] + r > a.height)
      return false;
    uniform = uniform && r == a.tileR[0];
  }
  if (!uniform)  // mixed sizes must nest: every r−1 a power of two
    for (int r : a.tileR)
      if (((r - 1) & (r - 2)) != 0) return false;
  return true;
}

}  // namespace fitdetail
}  // namespace vcgext
