#pragma once
/// Shared by the simplification's tests (quad_simplify_test.cpp and the tests of its pieces:
/// equalized_layout_test.cpp, coverage_test.cpp, budget_ladder_test.cpp, layout_trials_test.cpp):
/// the guarantees every final cage must keep, synthetic Fitmaps for real scans, a limit-to-input
/// distance, the cigar of the budget tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "test_support.h"
#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/quad/quad_mesh.h"
#include "vcg_ext/quad/quad_simplify.h"
#include "vcg_ext/quad/tri_to_quad.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace quadtest {

// The cigar of ThinPartGuardKeepsTheLimitOnAThinShape (an icosphere of 5 120 triangles squeezed to
// 0.08 across), flat Fitmaps (S 1, M 0.2) and a 12-patch budget without the M test: the budget
// ladder's case (its first pass stops at 24 patches).
struct CigarBudget {
  vcgext::TriData t = testsupport::Icosphere(4);
  std::vector<double> S, M;
  vcgext::QuadSimplifyParams p;
  CigarBudget() {
    for (auto& v : t.V) v = vcgext::Vec3(v[0], 0.08 * v[1], 0.08 * v[2]);
    S.assign(t.V.size(), 1.0);
    M.assign(t.V.size(), 0.2);
    p.targetPatches = 12;
    p.useMFitmap = false;
  }
};

// Guarantees on a final mesh but its flips: pure valid quads, no interior valence 2, Euler
// characteristic and boundary loops as the input, the patch count and valence histogram consistent.
inline void ExpectTopologyGuarantees(const vcgext::TriData& in, const vcgext::QuadSimplifyResult& r) {
  ASSERT_EQ(r.error, "");
  vcgext::quad::QuadMesh q(r.quads.V, r.quads.F);
  EXPECT_EQ(q.Check(), "");
  auto tq = vcgext::quad::TriToQuad(in);
  vcgext::quad::QuadMesh q0(tq.quads.V, tq.quads.F);
  auto i0 = q0.ComputeInvariants(), i1 = q.ComputeInvariants();
  EXPECT_EQ(i0.eulerPerComponent, i1.eulerPerComponent);
  EXPECT_EQ(i0.boundaryLoops, i1.boundaryLoops);
  EXPECT_EQ(r.patches, int(r.quads.F.size()));
  int sum = 0;
  for (int c : r.valenceHistogram) sum += c;
  EXPECT_EQ(sum, int(r.quads.V.size()));
  EXPECT_EQ(r.valenceHistogram.size() > 2 ? 0 : 1, 0);
}
// ... and all patches projectable with agreeing normals (a budget ladder's retry may keep flips its
// fit removes: BudgetFarBelowTheFirstPassTriesTheCoarseStartsFirst checks those by its rule).
inline void ExpectGuarantees(const vcgext::TriData& in, const vcgext::QuadSimplifyResult& r) {
  ExpectTopologyGuarantees(in, r);
  EXPECT_EQ(r.flippedPatches, 0);
  EXPECT_EQ(r.flippedVertices, 0);
}
// Synthetic Fitmaps for real scans: S from a normal-variation curvature estimate, M = 5% of
// the bbox diagonal.
inline void SyntheticFitmaps(const vcgext::TriData& t, std::vector<double>& S, std::vector<double>& M) {
  auto N = vcgext::VertexNormals(t);
  auto adj = vcgext::VertexVertexAdjacency(t.F, int(t.V.size()));
  double diag = vcgext::BBoxDiagonal(t.V);
  S.assign(t.V.size(), 0.0);
  M.assign(t.V.size(), 0.05 * diag);
  for (size_t i = 0; i < t.V.size(); ++i)
    for (const int* j = adj.Begin(int(i)); j != adj.End(int(i)); ++j) {
      double d = (t.V[*j] - t.V[i]).norm();
      if (d > 0) S[i] = std::max(S[i], std::sqrt((N[*j] - N[i]).norm() / d / diag));
    }
}
// RMS distance from the cage's limit (7 x 7 samples per patch) to the input (scene).
inline double RmsLimitDistance(const vcgext::QuadSimplifyResult& r, const vcgext::EmbreeScene& scene) {
  vcgext::LimitSurface ls = vcgext::LimitSurface::FromQuads(r.quads);
  EXPECT_TRUE(ls.Ok()) << ls.Error();
  double sum = 0;
  int n = 0;
  for (int f = 0; f < ls.NumFaces(); ++f)
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j, ++n) {
        vcgext::Vec3 P;
        ls.Evaluate(f, (i + 0.5) / 7, (j + 0.5) / 7, r.quads.V, &P);
        sum += (scene.ClosestPoint(P).point - P).squaredNorm();
      }
  return std::sqrt(sum / std::max(1, n));
}

}  // namespace quadtest
