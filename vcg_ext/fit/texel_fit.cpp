/// \file texel_fit.cpp
/// The least-squares texel fit (FitDisplacement) and the displaced surface it is fitted for
/// (DisplacedSurface): the per-tile surface or the renderer's grid (renderer_grid.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/renderer_grid.h"
#include "vcg_ext/fit/texel_space.h"

namespace vcgext {

using namespace fitdetail;

namespace {
// Segments per side of the displaced layer's patches: the tile's texel intervals, at least
// minSegments.
std::vector<int> DisplacedSegments(const DisplacementAtlas& a, int minSegments) {
  std::vector<int> n(a.tileR.size());
  for (size_t f = 0; f < n.size(); ++f) n[f] = std::max(a.tileR[f] - 1, minSegments);
  return n;
}

// The displaced layer as a linear function of the texel unknowns (TexelSpace): its base
// tessellation (what DisplacedSurface displaces) and, per base vertex, the weights of the
// unknowns in the bilinear filter of its patch's tile (4 texels, each 1 or 2 unknowns).
class DisplacedModel {
 public:
  static constexpr int kMaxTerms = 8;
  DisplacedModel(const LimitSurface& ls, const DisplacementAtlas& a, const LimitTessellation& base)
      : space_(ls, a), base_(base) {
    const int nB = NumBase();
    bt_.resize(nB);
    bw_.resize(nB);
    bn_.assign(nB, 0);
    for (int k = 0; k < nB; ++k) {
      const int f = base_.face[k];
      const TileCell c = CellAt(base_.uv[k], a.tileR[f] - 1);
      const int ti[4] = {c.i, c.i + 1, c.i, c.i + 1}, tj[4] = {c.j, c.j, c.j + 1, c.j + 1};
      for (int q = 0; q < 4; ++q) {
        if (c.w[q] == 0) continue;
        const TexelSpace::Term& t = space_.At(f, ti[q], tj[q]);
        for (int s = 0; s < t.n; ++s) {
          int slot = 0;
          while (slot < bn_[k] && bt_[k][slot] != t.id[s]) ++slot;
          if (slot == bn_[k]) {
            bt_[k][slot] = t.id[s];
            bw_[k][slot] = 0;
            ++bn_[k];
          }
          bw_[k][slot] += c.w[q] * t.w[s];
        }
      }
    }
  }
  const TexelSpace& Space() const { return space_; }
  int NumUnknowns() const { return space_.NumUnknowns(); }
  int NumBase() const { return int(base_.mesh.V.size()); }
  int Terms(int k) const { return bn_[k]; }
  const std::array<int, kMaxTerms>& Unknowns(int k) const { return bt_[k]; }
  const std::array<double, kMaxTerms>& Weights(int k) const { return bw_[k]; }
  double Displacement(int k, const Eigen::VectorXd& d) const {
    double s = 0;
    for (int q = 0; q < bn_[k]; ++q) s += bw_[k][q] * d[bt_[k][q]];
    return s;
  }
  TriData Mesh(const Eigen::VectorXd& d) const {
    TriData m;
    m.F = base_.mesh.F;
    m.V.resize(NumBase());
    for (int k = 0; k < NumBase(); ++k) m.V[k] = base_.mesh.V[k] + Displacement(k, d) * base_.normal[k];
    return m;
  }

 private:
  TexelSpace space_;
  const LimitTessellation& base_;
  std::vector<std::array<int, kMaxTerms>> bt_;
  std::vector<std::array<double, kMaxTerms>> bw_;
  std::vector<int> bn_;
};
}  // namespace

// The surface the atlas displaces (bake.h): each patch tessellated at its tile's spacing along the limit
// normals, or the renderer's uniform grid along its mesh normals (renderer_grid.h).
LimitTessellation DisplacementBase(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const DisplacementAtlas& a,
                                   int minSegments) {
  if (a.rendererLevel > 0) return RendererGrid(ls, ctrl, a.rendererLevel);
  return TessellateLimit(ls, ctrl, DisplacedSegments(a, minSegments));
}

DisplacementFitStats FitDisplacement(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const TriData& ref,
                                     int minSegments, double maxDist, const DisplacementFitParams& p,
                                     DisplacementAtlas& a) {
  if (!LayoutOk(a, ls.NumFaces())) return {};
  return FitDisplacement(ls, ref, DisplacementBase(ls, ctrl, a, minSegments), maxDist, p, a);
}

namespace {
// One point-to-plane row per reference vertex: its foot point's displacement along the displaced
// surface's normal m must close the gap to it (rowLen 0: no row).
struct DisplacementRows {
  static constexpr int kMaxRow = 3 * DisplacedModel::kMaxTerms;  // 3 triangle corners
  std::vector<std::array<int, kMaxRow>> idx;
  std::vector<std::array<double, kMaxRow>> w;
  std::vector<int> len;
  Eigen::VectorXd rhs, dist;  // per row: the gap along m; per reference vertex: its distance
  explicit DisplacementRows(int n) : idx(n), w(n), len(n), rhs(n), dist(n) {}
};

// The rows at the displaced mesh `dm` (displacements d): foot points of the reference vertices,
// exactly the reported error's closest points. Returns false when dm has no scene.
bool ProjectReference(const DisplacedModel& model, const LimitTessellation& base, const TriData& dm,
                      const TriData& ref, double maxDist, DisplacementRows& rows) {
  EmbreeScene scene(dm);
  if (!scene.Ok()) return false;
  const int nR = int(ref.V.size());
#pragma omp parallel
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (int r = 0; r < nR; ++r) {
      const Vec3& x = ref.V[r];
      const EmbreeScene::Hit h = scene.ClosestPoint(x, std::numeric_limits<double>::infinity(), hint);
      if (h.valid) hint = h.face;
      rows.len[r] = 0;
      rows.dist[r] = h.valid ? (h.point - x).norm() : 0.0;
      // no row for reference parts farther than the bake's range (not covered by the control
      // mesh, outliers): the texels must not be pulled there (they stay within ±maxDist)
      if (!h.valid || rows.dist[r] > maxDist) continue;
      const auto& tri = dm.F[h.face];
      const double b[3] = {1 - h.u - h.v, h.u, h.v};
      Vec3 m = (dm.V[tri[1]] - dm.V[tri[0]]).cross(dm.V[tri[2]] - dm.V[tri[0]]);
      if (!(m.norm() > 0)) m = b[0] * base.normal[tri[0]] + b[1] * base.normal[tri[1]] + b[2] * base.normal[tri[2]];
      if (!(m.norm() > 0)) continue;
      m.normalize();
      // Point-to-plane row: the foot's displacement along m must close the gap to x.
      Vec3 L = Vec3::Zero();
      int len = 0;
      for (int c = 0; c < 3; ++c) {
        const int k = tri[c];
        L += b[c] * base.mesh.V[k];
        const double ck = b[c] * base.normal[k].dot(m);
        for (int q = 0; q < model.Terms(k); ++q) {
          rows.idx[r][len] = model.Unknowns(k)[q];
          rows.w[r][len] = ck * model.Weights(k)[q];
          ++len;
        }
      }
      rows.len[r] = len;
      rows.rhs[r] = (x - L).dot(m);
    }
  }
  return true;
}

// Normal equations (AᵀA + w_a I) d = Aᵀb + w_a d0, solved into dn. False when the solve fails.
bool SolveAnchored(const DisplacementRows& rows, const Eigen::VectorXd& d0, double anchorWeight,
                   Eigen::VectorXd& dn) {
  const int nX = int(d0.size()), nR = int(rows.len.size());
  std::vector<Eigen::Triplet<double>> trip;
  size_t entries = size_t(nX);
  for (int r = 0; r < nR; ++r) entries += size_t(rows.len[r]) * rows.len[r];
  trip.reserve(entries);
  Eigen::VectorXd rhs = anchorWeight * d0;
  for (int r = 0; r < nR; ++r)
    for (int s1 = 0; s1 < rows.len[r]; ++s1) {
      rhs[rows.idx[r][s1]] += rows.w[r][s1] * rows.rhs[r];
      for (int s2 = 0; s2 < rows.len[r]; ++s2)
        trip.emplace_back(rows.idx[r][s1], rows.idx[r][s2], rows.w[r][s1] * rows.w[r][s2]);
    }
  for (int x = 0; x < nX; ++x) trip.emplace_back(x, x, anchorWeight);
  Eigen::SparseMatrix<double> Nm(nX, nX);
  Nm.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(Nm);
  if (solver.info() != Eigen::Success) return false;
  dn = solver.solve(rhs);
  return solver.info() == Eigen::Success && dn.allFinite();
}
}  // namespace

DisplacementFitStats FitDisplacement(const LimitSurface& ls, const TriData& ref, const LimitTessellation& base,
                                     double maxDist, const DisplacementFitParams& p, DisplacementAtlas& a) {
  DisplacementFitStats st;
  const int nF = ls.NumFaces();
  if (!ls.Ok() || nF == 0 || ref.V.empty() || p.iterations < 1 || !(p.anchorWeight > 0) || !(maxDist > 0))
    return st;
  // the atlas must be a layout of this surface (BakeDisplacement's)
  if (!LayoutOk(a, nF)) return st;
  const DisplacedModel model(ls, a, base);
  // Point-sampled (ray) values: the anchor of every texel.
  const Eigen::VectorXd d0 = model.Space().Gather(a);
  Eigen::VectorXd d = d0;
  const int nR = int(ref.V.size());
  DisplacementRows rows(nR);
  Eigen::VectorXd best = d;
  double bestRms = std::numeric_limits<double>::infinity();
  for (int it = 0; it <= p.iterations; ++it) {
    if (!ProjectReference(model, base, model.Mesh(d), ref, maxDist, rows)) break;
    double sum = 0;
    for (int r = 0; r < nR; ++r) sum += rows.dist[r] * rows.dist[r];
    const double rms = std::sqrt(sum / nR);
    if (it == 0) {
      st.rmsBefore = rms;
      st.fitted = true;  // evaluated: from here the stats are meaningful
    }
    if (!(rms < bestRms)) break;  // no improvement: keep the previous iterate
    bestRms = rms;
    best = d;
    st.iterations = it;
    if (it == p.iterations) break;
    Eigen::VectorXd dn;
    if (!SolveAnchored(rows, d0, p.anchorWeight, dn)) break;
    d = dn.cwiseMax(-maxDist).cwiseMin(maxDist);
  }
  st.rmsAfter = std::isfinite(bestRms) ? bestRms : st.rmsBefore;
  if (st.iterations > 0) {  // a solve was kept (else the atlas stays exactly as baked)
    model.Space().Scatter(best, a);
    Quantize(a);
  }
  return st;
}

LimitTessellation DisplacedSurface(const LimitSurface& ls, const std::vector<Vec3>& ctrl, const DisplacementAtlas& a,
                                   int minSegments) {
  if (!LayoutOk(a, ls.NumFaces()) || a.q16.size() != a.disp.size()) return {};
  return DisplacedSurface(ls, a, DisplacementBase(ls, ctrl, a, minSegments));
}

LimitTessellation DisplacedSurface(const LimitSurface& ls, const DisplacementAtlas& a, LimitTessellation t) {
  if (!LayoutOk(a, ls.NumFaces()) || a.q16.size() != a.disp.size()) return {};
  for (size_t v = 0; v < t.mesh.V.size(); ++v) {
    const int f = t.face[v];
    const TileCell c = CellAt(t.uv[v], a.tileR[f] - 1);
    const int i = c.i, j = c.j;
    const double d = c.w[0] * a.Decoded(f, i, j) + c.w[1] * a.Decoded(f, i + 1, j) +
                     c.w[2] * a.Decoded(f, i, j + 1) + c.w[3] * a.Decoded(f, i + 1, j + 1);
    t.mesh.V[v] += d * t.normal[v];
  }
  return t;
}

}  // namespace vcgext
