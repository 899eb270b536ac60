#pragma once
// Test shape of tests/fit: a quad "cube-sphere" control mesh.
#include <array>
#include <map>
#include <random>

#include "vcg_ext/core/indexed_mesh.h"

namespace fittest {

// Each cube face split s×s (6 s² quads, valence-3 vertices at the 8 cube corners), vertices moved
// towards the sphere of radius 0.5 by `sphereWeight` (1: on it) and radially perturbed by up to
// ±noise (relative, seeded).
inline vcgext::QuadData CubeSphere(int s, double noise, unsigned seed, double sphereWeight = 0.5) {
  using vcgext::Vec3;
  vcgext::QuadData q;
  std::map<std::array<int, 3>, int> id;
  auto vert = [&](std::array<int, 3> c) {
    auto it = id.find(c);
    if (it != id.end()) return it->second;
    Vec3 p(c[0] - s / 2.0, c[1] - s / 2.0, c[2] - s / 2.0);
    p /= s;
    p = (1 - sphereWeight) * p + sphereWeight * 0.5 * p.normalized();
    q.V.push_back(p);
    id[c] = int(q.V.size()) - 1;
    return int(q.V.size()) - 1;
  };
  struct Side { std::array<int, 3> o, u, v; };
  const Side sides[6] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 0, s}, {1, 0, 0}, {0, 1, 0}},
                         {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, s, 0}, {0, 0, 1}, {1, 0, 0}},
                         {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{s, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (const auto& sd : sides)
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        auto at = [&](int a, int b) {
          return std::array<int, 3>{sd.o[0] + a * sd.u[0] + b * sd.v[0], sd.o[1] + a * sd.u[1] + b * sd.v[1],
                                    sd.o[2] + a * sd.u[2] + b * sd.v[2]};
        };
        q.F.push_back({vert(at(i, j)), vert(at(i + 1, j)), vert(at(i + 1, j + 1)), vert(at(i, j + 1))});
      }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-noise, noise);
  for (auto& p : q.V) p *= 1.0 + U(rng);
  return q;
}

}  // namespace fittest
