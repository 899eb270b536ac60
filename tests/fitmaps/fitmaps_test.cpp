// Tests of vcgext::ComputeFitmaps (paper §3.1.2–3.1.3): analytic shapes with known answers,
// scale equivariance, Fast vs Reference agreement on a real scan, the vcg entry point, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "test_support.h"
#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/fitmaps/fitmaps.h"
#include "vcg_ext/fitmaps/fitmaps_internal.h"

using vcgext::FitmapParams;
using vcgext::FitmapResult;
using vcgext::TriData;
using vcgext::Vec3;

namespace {

FitmapResult RunFitmaps(const TriData& m, FitmapParams p) {
  vcgext::EmbreeScene scene(m);
  EXPECT_TRUE(scene.Ok()) << scene.Error();
  return vcgext::ComputeFitmaps(m, scene, p);
}

FitmapParams Mode(FitmapParams::Mode mode) {
  FitmapParams p;
  p.mode = mode;
  return p;
}

const FitmapParams::Mode kModes[] = {FitmapParams::Mode::Fast, FitmapParams::Mode::Reference};
const char* Name(FitmapParams::Mode m) { return m == FitmapParams::Mode::Fast ? "fast" : "reference"; }

int Nearest(const TriData& m, const Vec3& p) {
  int best = 0;
  for (size_t i = 0; i < m.V.size(); ++i)
    if ((m.V[i] - p).squaredNorm() < (m.V[best] - p).squaredNorm()) best = int(i);
  return best;
}

void ExpectAllFinite(const FitmapResult& r, const std::string& what) {
  ASSERT_EQ(r.error, "") << what;
  for (size_t i = 0; i < r.S.size(); ++i) {
    ASSERT_TRUE(std::isfinite(r.S[i]) && r.S[i] >= 0) << what << ": S[" << i << "] = " << r.S[i];
    ASSERT_TRUE(std::isfinite(r.M[i]) && r.M[i] > 0) << what << ": M[" << i << "] = " << r.M[i];
  }
}

std::vector<double> Ranks(const std::vector<double>& x) {
  std::vector<int> idx(x.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return x[a] < x[b]; });
  std::vector<double> r(x.size());
  for (size_t i = 0; i < idx.size();) {
    size_t j = i;
    while (j + 1 < idx.size() && x[idx[j + 1]] == x[idx[i]]) ++j;
    for (size_t k = i; k <= j; ++k) r[idx[k]] = 0.5 * double(i + j);
    i = j + 1;
  }
  return r;
}

double Spearman(const std::vector<double>& a, const std::vector<double>& b) {
  auto ra = Ranks(a), rb = Ranks(b);
  const double n = double(a.size());
  const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / n, mb = std::accumulate(rb.begin(), rb.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

/// A sheet folded back on itself: z = 0 for x in [0,1], a half circle of diameter `gap` at
/// x = 1, and z = gap for x back in [1,0]; y in [0, width]. Two close parallel sheets, connected.
TriData Hairpin(double gap, double h, double width) {
  std::vector<Vec3> profile;
  const int n = int(std::round(1.0 / h));
  for (int i = 0; i <= n; ++i) profile.emplace_back(i * h, 0, 0);
  const int nc = std::max(4, int(std::ceil(M_PI * gap / 2 / h)));
  for (int i = 1; i < nc; ++i) {
    const double a = -M_PI / 2 + M_PI * i / nc;
    profile.emplace_back(1.0 + gap / 2 * std::cos(a), 0, gap / 2 + gap / 2 * std::sin(a));
  }
  for (int i = n; i >= 0; --i) profile.emplace_back(i * h, 0, gap);
  const int ny = int(std::round(width / h));
  TriData m;
  for (int j = 0; j <= ny; ++j)
    for (const auto& q : profile) m.V.emplace_back(q[0], j * width / ny, q[2]);
  const int np = int(profile.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i + 1 < np; ++i) {
      const int a = j * np + i, b = a + 1, c = a + np, d = c + 1;
      m.F.push_back({a, b, d});
      m.F.push_back({a, d, c});
    }
  return m;
}

}  // namespace

// ---------------------------------------------------------------- building blocks

TEST(FitmapsInternal, CubicFitRecoversACubicExactly) {
  using namespace vcgext::fitmaps_internal;
  auto f = [](double u, double v) { return 0.3 - 0.2 * u + 0.5 * v * v + 0.7 * u * u * v - 0.4 * v * v * v; };
  CubicAccumulator acc;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-0.8, 0.8);
  std::vector<Vec3> pts;
  for (int k = 0; k < 40; ++k) {
    double u = U(rng), v = U(rng);
    acc.Add(u, v, f(u, v));
    pts.emplace_back(u, v, f(u, v));
  }
  Cubic g;
  ASSERT_TRUE(acc.Solve(0.8, g));
  for (const auto& q : pts) EXPECT_NEAR(g.Eval(q[0], q[1]), q[2], 1e-8);
  EXPECT_NEAR(g.Eval(0.1, -0.2), f(0.1, -0.2), 1e-8);
  // analytic normal of the graph: (-h_u, -h_v, 1) normalised
  const double u = 0.2, v = 0.1;
  const double hu = -0.2 + 1.4 * u * v, hv = v + 0.7 * u * u - 1.2 * v * v;
  EXPECT_LT((g.Normal(u, v) - Vec3(-hu, -hv, 1).normalized()).norm(), 1e-7);
  // closest point on the graph: the foot's normal line passes through the query point
  const Vec3 x(0.15, -0.1, 0.6);
  double fu, fv;
  ASSERT_TRUE(ClosestPointOnCubic(g, x, 2.0, fu, fv));
  const Vec3 P(fu, fv, g.Eval(fu, fv));
  EXPECT_LT((x - P).cross(g.Normal(fu, fv)).norm(), 1e-9);
}

TEST(FitmapsInternal, GatherIsAConnectedRegionNotABallQuery) {
  using namespace vcgext::fitmaps_internal;
  // Hairpin: the upper sheet lies 0.05 above the lower one, connected only at x = 1.
  TriData m = Hairpin(0.05, 0.05, 0.3);
  vcgext::Adjacency adj = vcgext::VertexVertexAdjacency(m.F, int(m.V.size()));
  const int src = Nearest(m, Vec3(0.3, 0.15, 0));
  GatherScratch s;
  std::vector<std::pair<int, double>> got;
  GatherMinimax(adj, m.V, src, 0.2, s, got);
  ASSERT_FALSE(got.empty());
  int ball = 0;
  for (size_t i = 0; i < m.V.size(); ++i) ball += (m.V[i] - m.V[src]).norm() <= 0.2 ? 1 : 0;
  for (auto& [q, k] : got) {
    EXPECT_LT(m.V[q][2], 0.01) << "the traversal jumped to the other sheet";
    EXPECT_LE((m.V[q] - m.V[src]).norm(), k + 1e-12);  // key >= own distance
  }
  EXPECT_LT(int(got.size()), ball);  // the ball also holds the upper sheet
  for (size_t i = 1; i < got.size(); ++i) EXPECT_LE(got[i - 1].second, got[i].second);  // prefix order
  // Larger radius than the way round the fold: the upper sheet is reached.
  GatherMinimax(adj, m.V, Nearest(m, Vec3(0.9, 0.15, 0)), 0.3, s, got);
  bool upper = false;
  for (auto& [q, k] : got) upper = upper || m.V[q][2] > 0.04;
  EXPECT_TRUE(upper);
}

// ---------------------------------------------------------------- analytic shapes

TEST(Fitmaps, PlaneHasZeroSAndLargestM) {
  TriData m = testsupport::PlaneGrid(30, 30, 2.0);
  for (auto mode : kModes) {
    FitmapResult r = RunFitmaps(m, Mode(mode));
    ExpectAllFinite(r, Name(mode));
    ASSERT_EQ(r.radii.size(), 9u);
    // r_0 = average edge length; r_h = 25% of the diagonal (2*sqrt(2))
    EXPECT_NEAR(r.radii.back(), 0.25 * 2.0 * std::sqrt(2.0), 1e-12);
    for (size_t i = 0; i < m.V.size(); ++i) {
      EXPECT_LT(r.S[i], 1e-5) << Name(mode) << " vertex " << i;  // residuals are round-off only
      EXPECT_EQ(r.M[i], r.radii.back()) << Name(mode) << " vertex " << i;
    }
  }
}

TEST(Fitmaps, ScalingScalesSByPowerMinusThreeQuartersAndMLinearly) {
  // E scales like s, r like s, so a = E / r^4 like s^-3 and a^{1/4} like s^{-3/4}.
  TriData m = testsupport::HeightField(24, 24, 1.0, [](double x, double y) {
    return 0.15 * std::sin(4 * x) * std::cos(3 * y) + 0.05 * x * x * x;
  });
  for (double s : {4.0, 0.3}) {
    TriData ms = m;
    for (auto& q : ms.V) q *= s;
    for (auto mode : kModes) {
      FitmapResult a = RunFitmaps(m, Mode(mode)), b = RunFitmaps(ms, Mode(mode));
      ASSERT_EQ(a.error, "");
      ASSERT_EQ(b.error, "");
      const double f = std::pow(s, -0.75);
      int sameM = 0, nonzero = 0;
      for (size_t i = 0; i < m.V.size(); ++i) {
        if (a.S[i] > 0) {
          ++nonzero;
          EXPECT_NEAR(b.S[i] / a.S[i], f, 1e-6 * f) << Name(mode) << " s=" << s << " vertex " << i;
        }
        sameM += std::abs(b.M[i] / a.M[i] - s) < 1e-9 * s ? 1 : 0;
      }
      EXPECT_GT(nonzero, int(m.V.size()) * 9 / 10);
      // M is a radius: the same radius index, scaled (threshold decisions may flip through
      // float rounding in Embree on a handful of vertices)
      EXPECT_GE(sameM, int(m.V.size()) * 99 / 100) << Name(mode) << " s=" << s;
    }
  }
}

TEST(Fitmaps, RmsResidualDoesNotDependOnSamplingDensity) {
  // Decision: E = sqrt(sum res^2 / n) (the paper prints (1/n) sqrt(sum res^2), which would
  // shrink like 1/sqrt(n) when the same surface is sampled twice as densely per axis: factor 2).
  auto f = [](double x, double y) { return 0.2 * std::sin(3 * x) * std::sin(3 * y); };
  TriData coarse = testsupport::HeightField(30, 30, 1.0, f), fine = testsupport::HeightField(60, 60, 1.0, f);
  FitmapParams p = Mode(FitmapParams::Mode::Reference);
  p.keepPerRadius = true;
  const int vc = Nearest(coarse, Vec3(0.5, 0.5, 0)), vf = Nearest(fine, Vec3(0.5, 0.5, 0));
  p.vertices = {vc};
  FitmapResult a = RunFitmaps(coarse, p);
  p.vertices = {vf};
  FitmapResult b = RunFitmaps(fine, p);
  ASSERT_EQ(a.error, "");
  ASSERT_EQ(b.error, "");
  const size_t H = a.radii.size();
  ASSERT_NEAR(a.radii.back(), b.radii.back(), 1e-4 * a.radii.back());  // same domain: same r_h
  const double ea = a.perRadiusE[vc * H + H - 1], eb = b.perRadiusE[vf * H + H - 1];
  ASSERT_GT(ea, 0);
  ASSERT_GT(eb, 0);
  EXPECT_NEAR(eb / ea, 1.0, 0.1);  // 1/n outside the root would give ~0.5
}

TEST(Fitmaps, LocalHighFrequencyBumpRaisesSAndLowersM) {
  // Flat square with a localised high-frequency bump whose crests overhang (a sheared wave):
  // the cubic cannot follow it (high S) and normal projection loses part of it (low M).
  const double size = 1.0;
  const int n = 80;
  TriData m = testsupport::PlaneGrid(n, n, size);
  for (auto& q : m.V) {
    const double d2 = (q[0] - 0.5) * (q[0] - 0.5) + (q[1] - 0.5) * (q[1] - 0.5);
    const double w = std::exp(-d2 / (2 * 0.08 * 0.08));
    const double ph = 2 * M_PI * q[0] / 0.1;  // wavelength 0.1 = 8 grid steps
    q[2] = 0.03 * w * std::sin(ph);
    q[0] += 0.03 * w * std::cos(ph);  // shear: crests lean over their troughs
  }
  FitmapParams p;
  p.maxRadiusPercent = 10;  // r_h = 0.14: neighbourhoods far from the bump do not see it
  const int onBump = Nearest(m, Vec3(0.5, 0.5, 0)), away = Nearest(m, Vec3(0.15, 0.15, 0));
  for (auto mode : kModes) {
    p.mode = mode;
    p.vertices = {onBump, away};
    FitmapResult r = RunFitmaps(m, p);
    ASSERT_EQ(r.error, "");
    EXPECT_GT(r.S[onBump], 5 * r.S[away]) << Name(mode);
    EXPECT_LT(r.M[onBump], r.M[away]) << Name(mode);
    EXPECT_EQ(r.M[away], r.radii.back()) << Name(mode);
  }
}

TEST(Fitmaps, CloseParallelSheetsGiveSmallM) {
  // Two sheets 0.02 apart, joined by a fold at x = 1. Near the fold, neighbourhoods larger
  // than the way round the fold hold both sheets: one cubic cannot project onto both.
  const double gap = 0.02;
  TriData m = Hairpin(gap, 0.02, 0.6);
  const int nearFold = Nearest(m, Vec3(0.96, 0.3, 0)), far = Nearest(m, Vec3(0.2, 0.3, 0));
  for (auto mode : kModes) {
    FitmapParams p = Mode(mode);
    p.vertices = {nearFold, far};
    FitmapResult r = RunFitmaps(m, p);
    ASSERT_EQ(r.error, "");
    // The other sheet is reached at about 0.04 + gap (0.04 to the fold plus its half turn):
    // the largest admissible radius must stay below three times that.
    EXPECT_LT(r.M[nearFold], 3 * (0.04 + gap)) << Name(mode);
    EXPECT_GT(r.M[far], 5 * r.M[nearFold]) << Name(mode);
  }
}

// ---------------------------------------------------------------- fast vs reference

TEST(Fitmaps, FastAgreesWithReferenceOnARealScan) {
  TriData m = testsupport::LoadSample("elephant.off");
  ASSERT_GT(m.V.size(), 1000u);
  vcgext::EmbreeScene scene(m);
  ASSERT_TRUE(scene.Ok());
  FitmapParams fp;  // default: Coverage estimator
  FitmapResult fast = vcgext::ComputeFitmaps(m, scene, fp);
  ASSERT_EQ(fast.error, "");
  FitmapParams fpPaper = fp;
  fpPaper.fastFlipEstimator = FitmapParams::FlipEstimator::ForwardSelf;
  FitmapResult fastPaper = vcgext::ComputeFitmaps(m, scene, fpPaper);
  ASSERT_EQ(fastPaper.error, "");
  std::vector<int> subset(m.V.size());
  std::iota(subset.begin(), subset.end(), 0);
  std::shuffle(subset.begin(), subset.end(), std::mt19937(7));
  subset.resize(400);
  FitmapParams rp;
  rp.mode = FitmapParams::Mode::Reference;
  rp.vertices = subset;
  FitmapResult ref = vcgext::ComputeFitmaps(m, scene, rp);  // the paper's density (factor 4)
  ASSERT_EQ(ref.error, "");
  FitmapParams rpDense = rp;
  rpDense.referenceSampleFactor = 32;  // converges towards the exact coverage
  FitmapResult refDense = vcgext::ComputeFitmaps(m, scene, rpDense);
  ASSERT_EQ(refDense.error, "");
  std::vector<double> fs, rs, fm, rm, fmPaper, rmDense, rel;
  for (int v : subset) {
    fs.push_back(fast.S[v]);
    rs.push_back(ref.S[v]);
    fm.push_back(fast.M[v]);
    fmPaper.push_back(fastPaper.M[v]);
    rm.push_back(ref.M[v]);
    rmDense.push_back(refDense.M[v]);
    rel.push_back(std::abs(fast.S[v] - ref.S[v]) / ref.S[v]);
  }
  std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
  // S: measured 0.99 / 0.5% (docs/fitmaps.md); the fast fits use sub-sampled points, so allow
  // some rank swaps among the many near-equal values of this mesh.
  EXPECT_GT(Spearman(fs, rs), 0.9);
  EXPECT_LT(rel[rel.size() / 2], 0.03);
  // M: Fast estimates a flipped share from 16 samples per neighbourhood (and interpolates the
  // large radii): the radius index is a coarse, threshold-decided value, so rank agreement is
  // moderate. Each estimator is compared with the Reference density it converges to
  // (ForwardSelf: the paper's factor 4, measured 0.79 on elephant; Coverage: a dense factor 32).
  EXPECT_GT(Spearman(fmPaper, rm), 0.6);
  EXPECT_GT(Spearman(fm, rmDense), 0.6);
  // Reference mode on a subset equals Reference mode on all vertices there (per-vertex values).
  std::vector<int> few(subset.begin(), subset.begin() + 5);
  rp.vertices = few;
  FitmapResult ref2 = vcgext::ComputeFitmaps(m, scene, rp);
  for (int v : few) {
    EXPECT_EQ(ref2.S[v], ref.S[v]);
    EXPECT_EQ(ref2.M[v], ref.M[v]);
  }
  // Fast mode on a subset equals the full Fast run there; uncomputed vertices are flagged.
  fp.vertices = few;
  FitmapResult fast2 = vcgext::ComputeFitmaps(m, scene, fp);
  for (int v : few) {
    EXPECT_EQ(fast2.S[v], fast.S[v]);
    EXPECT_EQ(fast2.M[v], fast.M[v]);
    EXPECT_EQ(fast2.computed[v], 1);
  }
  EXPECT_EQ(std::count(fast2.computed.begin(), fast2.computed.end(), 1), 5);
}

// ---------------------------------------------------------------- robustness

TEST(Fitmaps, AwkwardMeshesGiveFiniteValues) {
  // two components (one a sphere, one an open grid with boundary), a non-manifold vertex
  // (a third component glued to the sphere at one vertex), a zero-area face, isolated vertices
  TriData m = testsupport::Icosphere(3, 0.5);
  const int sphereN = int(m.V.size());
  TriData g = testsupport::PlaneGrid(12, 12, 1.0);
  for (auto q : g.V) m.V.push_back(q + Vec3(2, 0, 0));
  for (auto f : g.F) m.F.push_back({f[0] + sphereN, f[1] + sphereN, f[2] + sphereN});
  // a fan of two triangles touching the sphere's vertex 0 only (non-manifold vertex)
  const int a = int(m.V.size());
  m.V.push_back(m.V[0] + Vec3(0.3, 0.3, 0));
  m.V.push_back(m.V[0] + Vec3(0.3, -0.3, 0));
  m.V.push_back(m.V[0] + Vec3(0.6, 0, 0.1));
  m.F.push_back({0, a, a + 1});
  m.F.push_back({a, a + 2, a + 1});
  // a zero-area (collinear) face
  const int c = int(m.V.size());
  m.V.push_back(Vec3(-2, 0, 0));
  m.V.push_back(Vec3(-1.5, 0, 0));
  m.V.push_back(Vec3(-1, 0, 0));
  m.F.push_back({c, c + 1, c + 2});
  // unreferenced vertices
  const int u = int(m.V.size());
  m.V.push_back(Vec3(5, 5, 5));
  m.V.push_back(Vec3(-5, 5, 5));
  for (auto mode : kModes) {
    FitmapResult r = RunFitmaps(m, Mode(mode));
    ExpectAllFinite(r, Name(mode));
    EXPECT_EQ(r.unreferenced, 2) << Name(mode);
    for (int v : {u, u + 1}) {
      EXPECT_EQ(r.S[v], 0.0);
      EXPECT_EQ(r.M[v], r.radii.front());
    }
    // the collinear face's vertices have no normal of their own: PCA fallback, no crash
    EXPECT_GE(r.fallbackNormals, 3) << Name(mode);
  }
}

TEST(Fitmaps, FewRadiiAndExtremeRadiusWork) {
  TriData m = testsupport::Icosphere(2, 1.0);
  for (auto mode : kModes)
    for (int h : {1, 2, 3})
      for (double pct : {0.1, 100.0}) {
        FitmapParams p = Mode(mode);
        p.numRadii = h;
        p.maxRadiusPercent = pct;
        FitmapResult r = RunFitmaps(m, p);
        ExpectAllFinite(r, std::string(Name(mode)) + " h=" + std::to_string(h));
        ASSERT_EQ(int(r.radii.size()), h);
        for (size_t i = 1; i < r.radii.size(); ++i) EXPECT_GE(r.radii[i], r.radii[i - 1]);
        for (double M : r.M) EXPECT_TRUE(std::find(r.radii.begin(), r.radii.end(), M) != r.radii.end());
      }
}

TEST(Fitmaps, AnchoredRadiiDoNotDependOnTheEdgeLength) {
  // The paper's grid: numRadii radii from r_0 to r_h, geometric (the formula the grid had before
  // FitmapRadii).
  FitmapParams p;
  const double diag = 2.0, rh = 0.25 * diag;
  for (double r0 : {0.01, 0.004}) {
    const std::vector<double> paper = vcgext::FitmapRadii(r0, rh, diag, p);
    ASSERT_EQ(paper.size(), 9u);
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(paper[i], r0 * std::pow(rh / r0, i / 8.0), 1e-12 * rh);
  }
  // Anchored at r_h with the fixed ratio: a mesh 4x denser (r_0 / 2) keeps every radius of the
  // coarser one above its r_0, and with a floor above both r_0 the two grids are the same.
  p.minRadiusPercent = 0.01;  // below both r_0: the grid goes down to r_0
  const std::vector<double> coarse = vcgext::FitmapRadii(0.02, rh, diag, p);
  const std::vector<double> dense = vcgext::FitmapRadii(0.01, rh, diag, p);
  ASSERT_GE(coarse.size(), 2u);
  ASSERT_GT(dense.size(), coarse.size());
  const size_t extra = dense.size() - coarse.size();
  for (size_t i = 0; i < coarse.size(); ++i) EXPECT_DOUBLE_EQ(dense[extra + i], coarse[i]);
  EXPECT_GE(coarse.front(), 0.02 * (1 - 1e-9));
  EXPECT_LT(coarse.front(), 0.02 * vcgext::kAnchoredRadiusRatio);
  EXPECT_DOUBLE_EQ(coarse.back(), rh);
  for (size_t i = 1; i < dense.size(); ++i) EXPECT_NEAR(dense[i] / dense[i - 1], vcgext::kAnchoredRadiusRatio, 1e-9);
  p.minRadiusPercent = 2.0;  // 0.04, above both r_0
  EXPECT_EQ(vcgext::FitmapRadii(0.02, rh, diag, p), vcgext::FitmapRadii(0.005, rh, diag, p));
  EXPECT_GE(vcgext::FitmapRadii(0.005, rh, diag, p).front(), 0.04 * (1 - 1e-9));
  // On a mesh: M takes one of the radii, and the floor is respected.
  TriData m = testsupport::Icosphere(3, 1.0);
  p = Mode(FitmapParams::Mode::Fast);
  p.minRadiusPercent = 3.0;
  FitmapResult r = RunFitmaps(m, p);
  ExpectAllFinite(r, "anchored");
  const double d = 2.0 * std::sqrt(3.0) * 1.0;  // bbox diagonal of the unit sphere (up to tessellation)
  EXPECT_GE(r.radii.front(), 0.03 * d * 0.99);
  for (double M : r.M) EXPECT_TRUE(std::find(r.radii.begin(), r.radii.end(), M) != r.radii.end());
  p.minRadiusPercent = 30.0;  // above r_h: rejected
  EXPECT_NE(RunFitmaps(m, p).error, "");
}

TEST(Fitmaps, InvalidInputIsReported) {
  TriData plane = testsupport::PlaneGrid(4, 4);
  vcgext::EmbreeScene scene(plane);
  FitmapParams p;
  p.tauPercent = -1;
  EXPECT_NE(vcgext::ComputeFitmaps(plane, scene, p).error, "");
  p = FitmapParams();
  p.numRadii = 0;
  EXPECT_NE(vcgext::ComputeFitmaps(plane, scene, p).error, "");
  p = FitmapParams();
  p.maxRadiusPercent = 0;
  EXPECT_NE(vcgext::ComputeFitmaps(plane, scene, p).error, "");
  p = FitmapParams();
  p.vertices = {int(plane.V.size())};
  EXPECT_NE(vcgext::ComputeFitmaps(plane, scene, p).error.find("out of range"), std::string::npos);
  TriData other = testsupport::PlaneGrid(5, 5);
  EXPECT_NE(vcgext::ComputeFitmaps(other, scene, FitmapParams()).error, "");  // wrong scene
  TriData empty;
  vcgext::EmbreeScene es(plane);
  EXPECT_NE(vcgext::ComputeFitmaps(empty, es, FitmapParams()).error, "");
  TriData bad = plane;
  bad.V[3][1] = std::nan("");
  vcgext::EmbreeScene bs(plane);  // scene sizes match; the NaN is caught first
  EXPECT_NE(vcgext::ComputeFitmaps(bad, bs, FitmapParams()).error.find("vertex 3"), std::string::npos);
  TriData huge = plane;  // beyond what Embree represents (it aborts on such rays): an error, no ray
  for (auto& x : huge.V) x *= 1e19;
  vcgext::EmbreeScene hs(huge);
  EXPECT_NE(vcgext::ComputeFitmaps(huge, hs, FitmapParams()).error.find("beyond 1e17"), std::string::npos);
}

// ---------------------------------------------------------------- vcg entry point

TEST(Fitmaps, VcgEntryWritesAttributes) {
  TriData d = testsupport::Icosphere(2, 1.0);
  vcgext::TMesh m;
  testsupport::ToVcg(d, m);
  FitmapResult r = vcgext::ComputeFitmaps(m, FitmapParams());
  ASSERT_EQ(r.error, "");
  auto hS = vcg::tri::Allocator<vcgext::TMesh>::FindPerVertexAttribute<float>(m, vcgext::kFitmapSAttr);
  auto hM = vcg::tri::Allocator<vcgext::TMesh>::FindPerVertexAttribute<float>(m, vcgext::kFitmapMAttr);
  ASSERT_TRUE(vcg::tri::Allocator<vcgext::TMesh>::IsValidHandle(m, hS));
  ASSERT_TRUE(vcg::tri::Allocator<vcgext::TMesh>::IsValidHandle(m, hM));
  TriData imported;  // the same (float-rounded) coordinates the entry point sees
  ASSERT_EQ(vcgext::ImportTriangles(m, imported).error, "");
  FitmapResult direct = RunFitmaps(imported, FitmapParams());
  for (size_t i = 0; i < m.vert.size(); ++i) {
    EXPECT_FLOAT_EQ(hS[i], float(direct.S[i]));
    EXPECT_FLOAT_EQ(hM[i], float(direct.M[i]));
    EXPECT_GT(hS[i], 0.f);  // a sphere is curved: the cubic leaves a residual at large radii
  }
}

TEST(Fitmaps, VcgEntryRejectsBadLayersUntouched) {
  auto noAttr = [](vcgext::TMesh& m) {
    auto h = vcg::tri::Allocator<vcgext::TMesh>::FindPerVertexAttribute<float>(m, vcgext::kFitmapSAttr);
    return !vcg::tri::Allocator<vcgext::TMesh>::IsValidHandle(m, h);
  };
  {  // empty layer
    vcgext::TMesh m;
    EXPECT_NE(vcgext::ComputeFitmaps(m, FitmapParams()).error, "");
    EXPECT_TRUE(noAttr(m));
  }
  {  // point cloud
    vcgext::TMesh m;
    vcg::tri::Allocator<vcgext::TMesh>::AddVertices(m, 10);
    EXPECT_NE(vcgext::ComputeFitmaps(m, FitmapParams()).error.find("point cloud"), std::string::npos);
    EXPECT_TRUE(noAttr(m));
  }
  {  // NaN coordinates: error, coordinates and attributes untouched
    TriData d = testsupport::PlaneGrid(3, 3);
    vcgext::TMesh m;
    testsupport::ToVcg(d, m);
    m.vert[2].P()[0] = std::nanf("");
    const auto p5 = m.vert[5].P();
    EXPECT_NE(vcgext::ComputeFitmaps(m, FitmapParams()).error.find("NaN"), std::string::npos);
    EXPECT_TRUE(noAttr(m));
    EXPECT_EQ(m.vert[5].P(), p5);
  }
  {  // faces referring past the vertex array (what a corrupt file leaves): error, no attribute
    TriData d = testsupport::PlaneGrid(3, 3);
    vcgext::TMesh m;
    testsupport::ToVcg(d, m);
    m.face[3].V(1) = &m.vert[0] + 32600;  // never dereferenced: the bridge checks the range first
    EXPECT_NE(vcgext::ComputeFitmaps(m, FitmapParams()).error.find("do not exist"), std::string::npos);
    EXPECT_TRUE(noAttr(m));
  }
}

TEST(Fitmaps, VcgEntryRunsOnPolygonalLayersAndWorkingCopies) {
  // issue 16: faux edges are flags (the triangles are used); duplicates, unreferenced vertices
  // and flipped faces are handled on a working copy, with the same values as the clean mesh.
  TriData d = testsupport::Icosphere(2);
  vcgext::TMesh clean;
  testsupport::ToVcg(d, clean);
  ASSERT_EQ(vcgext::ComputeFitmaps(clean, FitmapParams()).error, "");
  auto hc = vcg::tri::Allocator<vcgext::TMesh>::FindPerVertexAttribute<float>(clean, vcgext::kFitmapSAttr);
  {
    vcgext::TMesh m;
    testsupport::ToVcg(d, m);
    m.face[0].SetF(1);
    m.face[1].SetF(0);
    vcgext::FitmapResult r = vcgext::ComputeFitmaps(m, FitmapParams());
    ASSERT_EQ(r.error, "");
    auto h = vcg::tri::Allocator<vcgext::TMesh>::FindPerVertexAttribute<float>(m, vcgext::kFitmapSAttr);
    for (size_t i = 0; i < d.V.size(); ++i) EXPECT_EQ(h[i], hc[i]) << i;
  }
  {  // every third face flipped, 20 stray vertices far away, each face listed twice
    TriData bad = d;
    for (size_t f = 0; f < bad.F.size(); f += 3) std::swap(bad.F[f][1], bad.F[f][2]);
    for (int i = 0; i < 20; ++i) bad.V.push_back(vcgext::Vec3(50 + i, 0, 0));
    const size_t nf = bad.F.size();
    for (size_t f = 0; f < nf; ++f) bad.F.push_back(bad.F[f]);
    vcgext::TMesh m;
    testsupport::ToVcg(bad, m);
    vcgext::FitmapResult r = vcgext::ComputeFitmaps(m, FitmapParams());
    ASSERT_EQ(r.error, "");
    EXPECT_EQ(r.notes.size(), 3u);  // repeated faces, unreferenced vertices, re-oriented faces
    auto h = vcg::tri::Allocator<vcgext::TMesh>::FindPerVertexAttribute<float>(m, vcgext::kFitmapSAttr);
    for (size_t i = 0; i < d.V.size(); ++i) EXPECT_NEAR(h[i], hc[i], 1e-4 * std::abs(hc[i]) + 1e-6) << i;
    for (size_t i = d.V.size(); i < bad.V.size(); ++i) EXPECT_EQ(h[i], 0.f);
  }
}

TEST(Fitmaps, WorkingResolutionAgreesWithTheFullComputation) {
  // issue 12: on a dense mesh the Fitmaps are computed on M' and interpolated to every vertex.
  // bunny00 (75k triangles) computed in full and from M' = 40k triangles. Measured: S Spearman
  // 0.984, median relative difference 1.1 %, M Spearman 0.93 (M takes 9 discrete radii).
  TriData b = testsupport::LoadSample("bunny00.off");
  vcgext::EmbreeScene scene(b);
  FitmapParams p;
  FitmapResult full = vcgext::ComputeFitmaps(b, scene, p);
  ASSERT_EQ(full.error, "");
  p.workingFaces = 40000;
  FitmapResult work = vcgext::ComputeFitmaps(b, scene, p);
  ASSERT_EQ(work.error, "");
  EXPECT_EQ(work.workingFaces, 40000);
  ASSERT_EQ(work.S.size(), b.V.size());
  std::vector<double> rel;
  for (size_t i = 0; i < b.V.size(); ++i) {
    ASSERT_TRUE(std::isfinite(work.S[i]) && std::isfinite(work.M[i]));
    EXPECT_EQ(work.computed[i], 1);
    rel.push_back(std::abs(work.S[i] - full.S[i]) / std::max(1e-12, full.S[i]));
  }
  std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
  const double sRho = Spearman(work.S, full.S), mRho = Spearman(work.M, full.M);
  std::printf("bunny00 from 40k: S Spearman %.3f, median rel. diff %.3f; M Spearman %.3f\n", sRho, rel[rel.size() / 2], mRho);
  EXPECT_GT(sRho, 0.95);
  EXPECT_LT(rel[rel.size() / 2], 0.05);
  EXPECT_GT(mRho, 0.85);
}

TEST(Fitmaps, ZeroAreaSliversAreFlippedOnTheWorkingResolutionAndSaid) {
  // A 64 x 64 height field (8 192 triangles) with 4 exactly collinear slivers in its flat half
  // (testsupport::GridWithZeroAreaFaces): "Compute Fitmaps" with a working resolution of 2 000 triangles decimates it
  // (before 2026-12-04 any zero-area face kept the full resolution) and its log says so.
  const TriData g = testsupport::GridWithZeroAreaFaces(4);
  vcgext::TMesh m;
  testsupport::ToVcg(g, m);
  FitmapParams p;
  p.workingFaces = 2000;
  FitmapResult r = vcgext::ComputeFitmaps(m, p);
  ASSERT_EQ(r.error, "");
  EXPECT_LE(r.workingFaces, 2000);
  EXPECT_GE(r.workingFaces, 1900);
  bool said = false;
  for (const auto& n : r.notes) said = said || n.find("edge flips removed zero-area triangles") != std::string::npos;
  EXPECT_TRUE(said);
  EXPECT_TRUE(r.warnings.empty());
  for (size_t i = 0; i < r.S.size(); ++i) ASSERT_TRUE(std::isfinite(r.S[i]) && std::isfinite(r.M[i]) && r.M[i] > 0) << i;
}

TEST(Fitmaps, DenseObjectOnASparseFloorIsPlannedOnCoarserLevelsWithTheSameFitmaps) {
  // FitmapParams::fastDenseBallFactor: a dense sphere (Icosphere(4), 5 120 triangles, radius 1)
  // on a sparse floor 60 x 60 (800 triangles) that holds most of the area: by the mean area per
  // vertex the radii up to the sphere's size stay on level 0, where every ball holds the whole
  // sphere (bunny00 on a floor 20 times its size: 108 s, 3.3 s with the guard). With the guard
  // they move to coarser levels and the sphere's Fitmaps stay what they were.
  TriData m = testsupport::Icosphere(4);
  const int sphereVertices = int(m.V.size());
  const int n = 20;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) m.V.push_back(Vec3(-30 + 60.0 * i / n, -1.05, -30 + 60.0 * j / n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = sphereVertices + i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
      m.F.push_back({a, b, d});
      m.F.push_back({a, d, c});
    }
  vcgext::EmbreeScene scene(m);
  FitmapParams p;
  p.fastDenseBallFactor = 0;
  const FitmapResult plain = vcgext::ComputeFitmaps(m, scene, p);
  const FitmapResult guarded = RunFitmaps(m, FitmapParams());
  ASSERT_EQ(plain.error, "");
  ASSERT_EQ(guarded.radiusLevel.size(), plain.radiusLevel.size());
  int moved = 0;
  for (size_t i = 0; i < plain.radiusLevel.size(); ++i) {
    EXPECT_GE(guarded.radiusLevel[i], plain.radiusLevel[i]);
    moved += plain.radiusLevel[i] == 0 && guarded.radiusLevel[i] > 0;
  }
  EXPECT_GE(moved, 1);
  std::vector<double> rel;
  int sameM = 0;
  for (int v = 0; v < sphereVertices; ++v) {
    rel.push_back(std::abs(guarded.S[v] - plain.S[v]) / std::max(1e-12, plain.S[v]));
    sameM += guarded.M[v] == plain.M[v];
  }
  std::nth_element(rel.begin(), rel.begin() + long(rel.size() / 2), rel.end());
  std::printf("sphere on a floor: %d radii moved off level 0, S median rel. diff %.4f, same M on %.1f %%\n", moved,
              rel[rel.size() / 2], 100.0 * sameM / sphereVertices);
  EXPECT_LT(rel[rel.size() / 2], 0.05);
  EXPECT_GT(sameM, 0.9 * sphereVertices);
}
