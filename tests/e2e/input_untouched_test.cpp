// Issue 16: a filter that fails leaves its input layer exactly as it was. In-process, on the vcg
// entry points every filter's glue calls: the layer's bytes (coordinates, face references,
// flags, quality, per-vertex attributes) are compared before and after each failure.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "test_support.h"
#include "vcg_ext/core/mesh_types.h"
#include "vcg_ext/fitmaps/fitmaps.h"
#include "vcg_ext/loop/loop_vcg.h"
#include "vcg_ext/quad/quad_simplify.h"

namespace {
using vcgext::TMesh;

// Everything a filter could change, as bytes.
std::string Snapshot(TMesh& m) {
  std::string s;
  auto put = [&](const void* p, size_t n) { s.append(static_cast<const char*>(p), n); };
  for (auto& v : m.vert) {
    put(&v.P(), sizeof v.P());
    put(&v.Q(), sizeof v.Q());
    int f = v.Flags();
    put(&f, sizeof f);
  }
  for (auto& f : m.face) {
    for (int k = 0; k < 3; ++k) {
      long i = long(f.V(k) - &m.vert[0]);
      put(&i, sizeof i);
    }
    int fl = f.Flags();
    put(&fl, sizeof fl);
  }
  auto h = vcg::tri::Allocator<TMesh>::FindPerVertexAttribute<float>(m, vcgext::kFitmapSAttr);
  bool has = vcg::tri::Allocator<TMesh>::IsValidHandle<float>(m, h);
  put(&has, sizeof has);
  if (has)
    for (size_t i = 0; i < m.vert.size(); ++i) put(&h[i], sizeof(float));
  s += std::to_string(m.vn) + "/" + std::to_string(m.fn);
  return s;
}

// Bad layers: every face degenerate (a repeated vertex), Möbius strip, NaN coordinate. (An edge
// of three triangles was one until the working copy learnt to separate them, input_prep.h.)
std::vector<vcgext::TriData> BadInputs() {
  std::vector<vcgext::TriData> out;
  vcgext::TriData degenerate;
  degenerate.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  degenerate.F = {{0, 1, 1}, {2, 2, 3}, {3, 0, 3}};
  out.push_back(degenerate);
  vcgext::TriData mobius;
  const int n = 12;
  for (int i = 0; i < n; ++i) {
    double a = 2 * M_PI * i / n, tw = a / 2;
    vcgext::Vec3 c(3 * std::cos(a), 3 * std::sin(a), 0), r(std::cos(a), std::sin(a), 0);
    vcgext::Vec3 d = std::cos(tw) * r + std::sin(tw) * vcgext::Vec3(0, 0, 1);
    mobius.V.push_back(c - 0.5 * d);
    mobius.V.push_back(c + 0.5 * d);
  }
  for (int i = 0; i < n; ++i) {
    int a = 2 * i, b = 2 * i + 1, c = 2 * ((i + 1) % n), d = c + 1;
    if (i == n - 1) std::swap(c, d);
    mobius.F.push_back({a, c, d});
    mobius.F.push_back({a, d, b});
  }
  out.push_back(mobius);
  vcgext::TriData nan = testsupport::Icosphere(1);
  nan.V[3][1] = std::nan("");
  out.push_back(nan);
  return out;
}
}  // namespace

TEST(InputUntouched, EveryEntryPointLeavesAFailedLayerAsItWas) {
  int failures = 0;
  for (const auto& bad : BadInputs()) {
    TMesh m;
    testsupport::ToVcg(bad, m);
    for (auto& v : m.vert) v.Q() = 7.0f;
    const std::string before = Snapshot(m);
    EXPECT_NE(vcgext::ComputeFitmaps(m, vcgext::FitmapParams()).error, "");
    EXPECT_EQ(Snapshot(m), before) << "Compute Fitmaps";
    EXPECT_NE(vcgext::SimplifyToQuads(m, vcgext::QuadSimplifyParams()).error, "");
    EXPECT_EQ(Snapshot(m), before) << "Fitmap Quad Simplification";
    TMesh out;
    EXPECT_NE(vcgext::LoopRefineMesh(m, out, vcgext::LoopSurfaceParams(), false, vcgext::LoopRefineParams()).error, "");
    EXPECT_EQ(Snapshot(m), before) << "Loop Refine";
    EXPECT_NE(vcgext::LoopCurvatureToQuality(m, vcgext::LoopSurfaceParams(), vcgext::LoopCurvatureKind(0)).error, "");
    EXPECT_EQ(Snapshot(m), before) << "Loop Curvature";
    TMesh pts;
    testsupport::ToVcg(testsupport::Icosphere(0), pts);
    const std::string ptsBefore = Snapshot(pts);
    EXPECT_NE(vcgext::LoopSnapVertices(pts, m, vcgext::LoopSurfaceParams()).error, "");
    EXPECT_EQ(Snapshot(pts), ptsBefore) << "Loop Snap (points)";
    EXPECT_EQ(Snapshot(m), before) << "Loop Snap (net)";
    ++failures;
  }
  EXPECT_EQ(failures, 3);
}
