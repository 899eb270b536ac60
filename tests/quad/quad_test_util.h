#pragma once
/// Hand-built quad meshes for the quad tests.
#include <map>
#include <tuple>

#include <Eigen/Geometry>

#include "vcg_ext/core/indexed_mesh.h"

namespace quadtest {

/// Open nx x ny grid of quads on [0,size]^2 at z = 0, counter-clockwise seen from +z.
inline vcgext::QuadData QuadGrid(int nx, int ny, double size = 1.0) {
  vcgext::QuadData q;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) q.V.emplace_back(size * i / nx, size * j / ny, 0.0);
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) q.F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return q;
}

/// Surface of the cube [-1,1]^3 with n x n quads per side (outward orientation); if `sphere`,
/// vertices are pushed onto the unit sphere. Corners have valence 3.
inline vcgext::QuadData CubeSphere(int n, bool sphere = true) {
  vcgext::QuadData q;
  std::map<std::tuple<int, int, int>, int> ids;
  auto vid = [&](int x, int y, int z) {
    auto key = std::make_tuple(x, y, z);
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    vcgext::Vec3 p(2.0 * x / n - 1, 2.0 * y / n - 1, 2.0 * z / n - 1);
    if (sphere) p.normalize();
    q.V.push_back(p);
    return ids[key] = int(q.V.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto P = [&](int a, int b) {
            int c[3];
            c[axis] = side * n;
            c[(axis + 1) % 3] = a;
            c[(axis + 2) % 3] = b;
            return vid(c[0], c[1], c[2]);
          };
          vcgext::Quad f{P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)};
          vcgext::Vec3 nrm = (q.V[f[1]] - q.V[f[0]]).cross(q.V[f[3]] - q.V[f[0]]);
          vcgext::Vec3 out = vcgext::Vec3::Zero();
          out[axis] = side ? 1 : -1;
          if (nrm.dot(out) < 0) std::swap(f[1], f[3]);
          q.F.push_back(f);
        }
  return q;
}

/// Triangulates quads (diagonal 0-2).
inline vcgext::TriData Triangulate(const vcgext::QuadData& q) {
  vcgext::TriData t;
  t.V = q.V;
  for (auto& f : q.F) {
    t.F.push_back({f[0], f[1], f[2]});
    t.F.push_back({f[0], f[2], f[3]});
  }
  return t;
}

}  // namespace quadtest
