// Tests of the surface a renderer rebuilds (issue 15, vcg_ext/fit/renderer_grid.h): the level-L
// grid's mesh normals against an independent brute-force computation, their convergence to the
// limit normal, the grid indexing, and the bake for that grid (FitBakeParams::rendererGrid).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "cube_sphere.h"
#include "test_support.h"
#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/fit_internal.h"
#include "vcg_ext/fit/renderer_grid.h"

using namespace vcgext;

namespace {

// The cube-sphere on the sphere (valence-3 corners), radially perturbed.
vcgext::QuadData PerturbedCubeSphere(int s, double noise, unsigned seed) {
  return fittest::CubeSphere(s, noise, seed, 1.0);
}

double Angle(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

}  // namespace

// Blender's rule computed from scratch: every grid point of every patch evaluated on its own,
// the quads meeting at a point found by position (no shared indices), angle-weighted sums.
TEST(RendererGrid, MatchABruteForceAngleWeightedSum) {
  const QuadData q = PerturbedCubeSphere(2, 0.1, 3);  // 24 patches, valence-3 corners
  const LimitSurface ls = LimitSurface::FromQuads(q);
  ASSERT_TRUE(ls.Ok());
  const int L = 2, N = 1 << L;
  const LimitTessellation t = RendererGrid(ls, q.V, L);
  ASSERT_EQ(t.N, N);
  const int nF = ls.NumFaces();
  // positions per (patch, i, j), each from its own patch's parameters
  std::vector<Vec3> P(size_t(nF) * (N + 1) * (N + 1));
  auto at = [&](int f, int i, int j) -> Vec3& { return P[(size_t(f) * (N + 1) + j) * (N + 1) + i]; };
  for (int f = 0; f < nF; ++f)
    for (int j = 0; j <= N; ++j)
      for (int i = 0; i <= N; ++i) {
        Vec3 n;
        at(f, i, j) = fitdetail::LimitPointNormal(ls, q.V, f, double(i) / N, double(j) / N, &n);
        // the grid indexing finds that same point
        EXPECT_LT((t.mesh.V[GridVertex(t, f, i, j)] - at(f, i, j)).norm(), 1e-9) << f << " " << i << " " << j;
      }
  const double tol = 1e-9;
  for (int f = 0; f < nF; ++f)
    for (int j = 0; j <= N; ++j)
      for (int i = 0; i <= N; ++i) {
        const Vec3 x = at(f, i, j);
        Vec3 sum = Vec3::Zero();
        for (int g = 0; g < nF; ++g)
          for (int cj = 0; cj < N; ++cj)
            for (int ci = 0; ci < N; ++ci) {
              const Vec3 c[4] = {at(g, ci, cj), at(g, ci + 1, cj), at(g, ci + 1, cj + 1), at(g, ci, cj + 1)};
              const Vec3 n = (c[2] - c[0]).cross(c[3] - c[1]).normalized();
              for (int k = 0; k < 4; ++k)
                if ((c[k] - x).norm() < tol) {
                  const Vec3 a = c[(k + 3) % 4] - c[k], b = c[(k + 1) % 4] - c[k];
                  sum += std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * n;
                }
            }
        const Vec3 expect = sum.normalized();
        EXPECT_LT((t.normal[GridVertex(t, f, i, j)] - expect).norm(), 1e-9) << f << " " << i << " " << j;
      }
}

// The mesh normals approach the limit normals as the level grows (everywhere, extraordinary
// corners included), and point to the same side.
TEST(RendererGrid, ConvergeToTheLimitNormal) {
  const QuadData q = PerturbedCubeSphere(3, 0.15, 5);
  const LimitSurface ls = LimitSurface::FromQuads(q);
  ASSERT_TRUE(ls.Ok());
  std::vector<double> worst;
  for (int L = 1; L <= 5; ++L) {
    const LimitTessellation exact = TessellateLimit(ls, q.V, 1 << L);
    const LimitTessellation mesh = RendererGrid(ls, q.V, L);
    ASSERT_EQ(exact.normal.size(), mesh.normal.size());
    double w = 0;
    for (size_t v = 0; v < mesh.normal.size(); ++v) {
      EXPECT_GT(mesh.normal[v].dot(exact.normal[v]), 0.0);
      w = std::max(w, Angle(mesh.normal[v], exact.normal[v]));
    }
    worst.push_back(w);
  }
  // first order at least (halving the spacing at least halves the worst angle, with slack for
  // the extraordinary corners' slower rate): measured
  for (size_t k = 1; k < worst.size(); ++k) EXPECT_LT(worst[k], 0.75 * worst[k - 1]) << "level " << k + 1;
  EXPECT_LT(worst.back(), 0.02);  // radians, level 5
}

TEST(RendererGrid, LevelFollowsTheLargestTile) {
  DisplacementAtlas a;
  a.tileR = {3, 9, 17, 5};
  EXPECT_EQ(RendererLevel(a), 4);
  a.tileR = {3, 3};
  EXPECT_EQ(RendererLevel(a), 1);
  a.tileR = {6, 6};  // a uniform R that is not 2^k + 1: texels off the grid
  EXPECT_EQ(RendererLevel(a), 0);
}

// The bake for the renderer's grid: the displaced layer is the level-L grid moved along its mesh
// normals by the bilinear atlas value, rebuilt here as Blender does from the atlas and the wedge
// UVs; and under that reconstruction this atlas fits the reference better than the default one.
TEST(RendererGrid, BakeForItIsWhatTheRendererRebuilds) {
  TriData ref = testsupport::Icosphere(5, 0.5);
  for (auto& p : ref.V) {
    const Vec3 n = p.normalized();
    p = n * (0.5 + 0.02 * std::sin(9 * n[0]) * std::sin(7 * n[1]) * std::cos(5 * n[2]));
  }
  const EmbreeScene scene(ref);
  const QuadData q = PerturbedCubeSphere(3, 0.0, 1);  // 54 patches
  FitBakeParams bp;
  FitBakeResult lim = FitAndBake(q, ref, scene, bp);
  bp.rendererGrid = true;
  FitBakeResult mesh = FitAndBake(q, ref, scene, bp);  // "mesh": baked for the renderer's grid
  ASSERT_TRUE(lim.error.empty() && mesh.error.empty());
  EXPECT_EQ(lim.atlas.rendererLevel, 0);
  const int L = mesh.atlas.rendererLevel;
  ASSERT_EQ(L, RendererLevel(mesh.atlas));
  ASSERT_GE(L, 1);
  EXPECT_TRUE(mesh.warnings.empty());
  // the displaced layer rebuilt independently from the atlas, the grid and the wedge UVs
  const LimitSurface ls = LimitSurface::FromQuads(mesh.fit.control);
  const LimitTessellation grid = RendererGrid(ls, mesh.fit.control.V, L);
  const DisplacementAtlas& a = mesh.atlas;
  const LimitTessellation& D = mesh.displaced;
  ASSERT_EQ(D.face.size(), D.mesh.V.size());
  ASSERT_EQ(D.mesh.V.size(), grid.mesh.V.size());
  double worst = 0;
  int onGrid = 0;
  for (size_t v = 0; v < D.mesh.V.size(); ++v) {
    const int f = D.face[v];
    const double u = D.uv[v][0], w = D.uv[v][1];
    const double gi = u * grid.N, gj = w * grid.N;
    // every vertex of the displaced layer is a grid vertex
    if (std::abs(gi - std::round(gi)) > 1e-9 || std::abs(gj - std::round(gj)) > 1e-9) continue;
    ++onGrid;
    // texture position from the wedge UVs (bilinear in the quad, UV smooth "none"), in texels
    const auto& c = a.wedgeUV[f];
    const Eigen::Vector2d uv = (1 - u) * (1 - w) * c[0] + u * (1 - w) * c[1] + u * w * c[2] + (1 - u) * w * c[3];
    const double x = uv[0] * a.width - 0.5, y = (1 - uv[1]) * a.height - 0.5;
    // a corner texel's centre can come out a rounding below 0 (a tile at the image's edge): clamp
    const int x0 = std::clamp(int(std::floor(x)), 0, a.width - 2), y0 = std::clamp(int(std::floor(y)), 0, a.height - 2);
    const double fx = x - x0, fy = y - y0;
    auto val = [&](int xx, int yy) { return a.offset + a.scale * a.q16[size_t(yy) * a.width + xx]; };
    const double d = (1 - fy) * ((1 - fx) * val(x0, y0) + fx * val(x0 + 1, y0)) +
                     fy * ((1 - fx) * val(x0, y0 + 1) + fx * val(x0 + 1, y0 + 1));
    const int g = GridVertex(grid, f, int(std::round(gi)), int(std::round(gj)));
    worst = std::max(worst, (grid.mesh.V[g] + d * grid.normal[g] - D.mesh.V[v]).norm());
  }
  EXPECT_EQ(onGrid, int(D.mesh.V.size()));
  // exact inside a patch; on a shared edge the vertex belongs to one of its patches, whose texels
  // agree with the other's up to one 16-bit rounding of the finer tile's interpolated texels
  EXPECT_LE(worst, 1.01 * a.scale);
  EXPECT_GT(a.scale, 0.0);
  // the default atlas (per-tile surface, limit normals) rebuilt by the renderer is off by more
  DisplacementAtlas misread = lim.atlas;
  misread.rendererLevel = L;
  const LimitTessellation wrong = DisplacedSurface(LimitSurface::FromQuads(lim.fit.control), lim.fit.control.V, misread);
  const double pm = 1000.0 / BBoxDiagonal(ref.V);
  const double misreadRms = ReferenceToSurfaceError(ref, wrong.mesh).first * pm;
  EXPECT_LT(mesh.metrics.rmsDisplacedPermille, misreadRms);
  // same fit: only the displacement differs
  EXPECT_DOUBLE_EQ(mesh.metrics.rmsLimitPermille, lim.metrics.rmsLimitPermille);
  std::printf("displaced RMS permille: default bake %.4f, rebuilt on the renderer's grid %.4f; bake for it %.4f\n",
              lim.metrics.rmsDisplacedPermille, misreadRms, mesh.metrics.rmsDisplacedPermille);
}

// A user-set R that is not 2^k + 1 keeps the per-tile surface, with a warning.
TEST(RendererGrid, OffGridTilesFallBackToThePerTileSurfaceWithAWarning) {
  const TriData ref = testsupport::Icosphere(4, 0.5);
  const EmbreeScene scene(ref);
  FitBakeParams bp;
  bp.rendererGrid = true;
  bp.textureResolution = 6;
  const FitBakeResult r = FitAndBake(PerturbedCubeSphere(2, 0.0, 1), ref, scene, bp);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_EQ(r.atlas.rendererLevel, 0);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("2^k+1 texels"), std::string::npos);
}
