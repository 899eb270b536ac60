/// \file atlas_layout.cpp
/// The displacement atlas's layout (bake.h): automatic budgets, uniform and adaptive tile
/// layouts, the adaptive tile sizes and their inputs (patch areas, reference vertices per patch).
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/fit_internal.h"

namespace vcgext {

int AutoTextureResolution(int referenceVertices, int patches) {
  if (patches <= 0) return kMinAutoTextureResolution;
  return std::max(kMinAutoTextureResolution, int(std::lround(std::sqrt(double(referenceVertices) / patches))));
}

double AutoTextureBudget(int referenceVertices, int patches) {
  return std::max(double(referenceVertices),
                  double(kMinAutoTextureResolution) * kMinAutoTextureResolution * std::max(patches, 0));
}

long long DisplacementAtlas::Samples() const {
  long long n = 0;
  for (int r : tileR) n += (long long)r * r;
  return n;
}

void UniformAtlasLayout(DisplacementAtlas& a, int F, int R) {
  a.adaptive = false;
  a.R = R;
  a.cols = std::max(1, int(std::ceil(std::sqrt(double(F)))));
  a.rows = (F + a.cols - 1) / a.cols;
  a.width = a.cols * R;
  a.height = a.rows * R;
  a.tileR.assign(F, R);
  a.tileX.resize(F);
  a.tileY.resize(F);
  for (int f = 0; f < F; ++f) {
    a.tileX[f] = (f % a.cols) * R;
    a.tileY[f] = (f / a.cols) * R;
  }
  a.disp.assign(size_t(a.width) * a.height, 0.f);
}

void AdaptiveAtlasLayout(DisplacementAtlas& a, const std::vector<int>& tileR) {
  const int F = int(tileR.size());
  a.adaptive = true;
  a.cols = a.rows = 0;
  a.tileR = tileR;
  a.tileX.assign(F, 0);
  a.tileY.assign(F, 0);
  a.R = 0;
  long long area = 0;
  for (int r : tileR) {
    a.R = std::max(a.R, r);
    area += (long long)r * r;
  }
  // Shelf packing, tallest tiles first (ties by patch index: deterministic).
  std::vector<int> order(F);
  for (int f = 0; f < F; ++f) order[f] = f;
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return tileR[x] > tileR[y]; });
  a.width = std::max(a.R, int(std::ceil(std::sqrt(double(area)))));
  int x = 0, y = 0, shelf = 0;
  for (int f : order) {
    if (x + tileR[f] > a.width) {
      y += shelf;
      x = 0;
      shelf = 0;
    }
    a.tileX[f] = x;
    a.tileY[f] = y;
    x += tileR[f];
    shelf = std::max(shelf, tileR[f]);
  }
  a.height = y + shelf;
  a.disp.assign(size_t(a.width) * a.height, 0.f);
}

namespace {

// The tile sizes' knapsack (AdaptiveTileResolutions): per patch f a level k of kTileLevels, costing
// extra[k] spare units and leaving W[f] * err[k] of squared error; the levels that minimize the
// error within `units`.
constexpr int kTileLevels = 6;  // T = 2, 4, …, 64: tiles of 3 .. 65 texels per side
struct TileKnapsack {
  std::vector<double> W;
  int extra[kTileLevels];
  double err[kTileLevels];
  long long units = 0;
};

// Exact: dynamic programming over the spare units (bunny00: 379 × 4.3k cells).
std::vector<int> KnapsackExact(const TileKnapsack& q) {
  const int F = int(q.W.size());
  const auto& W = q.W;
  const auto& extra = q.extra;
  const auto& err = q.err;
  std::vector<int> level(F, 0);
  const int S = int(q.units);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> best(S + 1, inf), next(S + 1);
  best[0] = 0;
  std::vector<std::uint8_t> choice(size_t(F) * (S + 1), 0);
  for (int f = 0; f < F; ++f) {
    std::fill(next.begin(), next.end(), inf);
    std::uint8_t* ch = choice.data() + size_t(f) * (S + 1);
    for (int k = 0; k < kTileLevels; ++k) {
      const double e = W[f] * err[k];
      for (int s = extra[k]; s <= S; ++s) {
        const double v = best[s - extra[k]] + e;
        if (v < next[s]) {  // ties: the smaller tile (k ascending)
          next[s] = v;
          ch[s] = std::uint8_t(k);
        }
      }
    }
    best.swap(next);
  }
  int s = int(std::min_element(best.begin(), best.end()) - best.begin());
  for (int f = F - 1; f >= 0; --f) {
    level[f] = choice[size_t(f) * (S + 1) + s];
    s -= extra[level[f]];
  }
  return level;
}

// Many patches: Lagrangian relaxation (each patch minimizes W·err + λ·extra on its own; the
// smallest λ that fits, by bisection), then the best upgrades that still fit. Optimal up to the
// leftover of one knapsack step, which is small against a budget this large.
std::vector<int> KnapsackLagrangian(const TileKnapsack& q) {
  const int F = int(q.W.size());
  const auto& W = q.W;
  const auto& extra = q.extra;
  const auto& err = q.err;
  const long long units = q.units;
  std::vector<int> level(F, 0);
  double maxW = 0;
  for (double w : W) maxW = std::max(maxW, w);
  auto choose = [&](double lambda, std::vector<int>& out) {
    long long n = 0;
    for (int f = 0; f < F; ++f) {
      int bk = 0;
      for (int k = 1; k < kTileLevels; ++k)
        if (W[f] * err[k] + lambda * extra[k] < W[f] * err[bk] + lambda * extra[bk]) bk = k;
      out[f] = bk;
      n += extra[bk];
    }
    return n;
  };
  std::vector<int> trial(F);
  double lo = std::log(std::max(maxW, 1e-300)) - 80, hi = std::log(std::max(maxW, 1e-300)) + 5;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (choose(std::exp(mid), trial) <= units ? hi : lo) = mid;
  }
  long long used = choose(std::exp(hi), level);
  for (;;) {
    int bf = -1;
    double bestRate = 0;
    for (int f = 0; f < F; ++f) {
      const int k = level[f];
      if (k + 1 >= kTileLevels || used + extra[k + 1] - extra[k] > units) continue;
      const double rate = W[f] * (err[k] - err[k + 1]) / (extra[k + 1] - extra[k]);
      if (rate > bestRate) { bestRate = rate; bf = f; }
    }
    if (bf < 0) break;
    used += extra[level[bf] + 1] - extra[level[bf]];
    ++level[bf];
  }
  return level;
}

}  // namespace

std::vector<int> AdaptiveTileResolutions(const std::vector<double>& patchArea, const std::vector<double>& patchVertices,
                                         double budget) {
  const int F = int(patchArea.size());
  std::vector<int> R(F, 3);
  if (F == 0 || int(patchVertices.size()) != F) return R;
  // Error model: a reference vertex on patch f is off the bilinear displaced layer by about the
  // texel spacing √(area_f)/T_f (measured on bunny00: the RMS per patch grows linearly with the
  // spacing), so the squared error summed over the reference vertices is Σ_f W_f / T_f² with
  // W_f = vertices_f · area_f, to minimize under Σ (T_f+1)² <= budget: a multiple-choice
  // knapsack. Every patch pays for its 3×3 tile first; (T+1)² − 9 = 8·c with
  // c = 0, 2, 9, 35, 135, 527 extra units of 8 texels.
  TileKnapsack q;
  q.W.resize(F);
  for (int f = 0; f < F; ++f) q.W[f] = std::max(patchVertices[f], 0.0) * std::max(patchArea[f], 0.0);
  for (int k = 0; k < kTileLevels; ++k) {
    const int t = 2 << k;
    q.extra[k] = ((t + 1) * (t + 1) - 9) / 8;
    q.err[k] = 1.0 / (double(t) * t);
  }
  const double spare = (budget - 9.0 * F) / 8.0;
  if (!(spare >= 1)) return R;  // no room beyond the smallest tiles
  q.units = (long long)std::min(spare, double(q.extra[kTileLevels - 1]) * F);
  const std::vector<int> level = double(F) * double(q.units + 1) <= 4e7 ? KnapsackExact(q) : KnapsackLagrangian(q);
  for (int f = 0; f < F; ++f) R[f] = (2 << level[f]) + 1;
  return R;
}

std::vector<double> PatchVertexCounts(const LimitTessellation& t, int patches, const TriData& ref) {
  std::vector<double> n(std::max(patches, 0), 0.0);
  const EmbreeScene s(t.mesh);
  if (!s.Ok()) return n;
  std::vector<int> owner(ref.V.size(), -1);
#pragma omp parallel
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long v = 0; v < long(ref.V.size()); ++v) {
      const EmbreeScene::Hit h = s.ClosestPoint(ref.V[v], std::numeric_limits<double>::infinity(), hint);
      if (h.valid) hint = h.face;
      if (h.valid && h.face < int(t.triPatch.size())) owner[v] = t.triPatch[h.face];
    }
  }
  for (int o : owner)
    if (o >= 0 && o < patches) n[o] += 1;
  return n;
}

std::vector<double> PatchAreas(const LimitTessellation& t, int patches) {
  std::vector<double> area(std::max(patches, 0), 0.0);
  for (size_t k = 0; k < t.mesh.F.size() && k < t.triPatch.size(); ++k) {
    const auto& f = t.mesh.F[k];
    const int p = t.triPatch[k];
    if (p < 0 || p >= patches) continue;
    area[p] += 0.5 * (t.mesh.V[f[1]] - t.mesh.V[f[0]]).cross(t.mesh.V[f[2]] - t.mesh.V[f[0]]).norm();
  }
  return area;
}

}  // namespace vcgext
