#pragma once
/// The analytic shape of the multi-resolution tests (multires_test.cpp, working_start_test.cpp):
/// the bumpy sphere r(d) = 1 + 0.05 sin 3x sin 3y sin 3z, |d| = 1, and a cage limit's distance to it.
#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace quadtest {

inline double BumpyRadius(const vcgext::Vec3& d) {
  return 1.0 + 0.05 * std::sin(3 * d[0]) * std::sin(3 * d[1]) * std::sin(3 * d[2]);
}
/// The icosphere of `level` (20 x 4^level triangles) on the bumpy sphere.
inline vcgext::TriData BumpySphere(int level) {
  vcgext::TriData t = testsupport::Icosphere(level);
  for (auto& p : t.V) p *= BumpyRadius(p.normalized());
  return t;
}
/// RMS radial distance of the limit surface of `q` (5 x 5 samples per patch) to the bumpy sphere.
inline double BumpyLimitRms(const vcgext::QuadData& q) {
  vcgext::LimitSurface ls = vcgext::LimitSurface::FromQuads(q);
  EXPECT_TRUE(ls.Ok());
  double sum = 0;
  int n = 0;
  for (int f = 0; f < ls.NumFaces(); ++f)
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j) {
        vcgext::Vec3 P;
        ls.Evaluate(f, (i + 0.5) / 5, (j + 0.5) / 5, q.V, &P);
        const double d = P.norm() - BumpyRadius(P.normalized());
        sum += d * d;
        ++n;
      }
  return n ? std::sqrt(sum / n) : 0.0;
}

}  // namespace quadtest
