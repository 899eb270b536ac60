/// \file scan_artifacts.cpp
/// Debris, small holes, doubled walls and thin sheets of a raw scan, and what they cost the cage (scan_artifacts.h).
#include "vcg_ext/quad/scan_artifacts.h"

#include "vcg_ext/core/union_find.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Geometry>

namespace vcgext {

namespace {
// The pieces of a mesh (faces joined at shared vertices, UnionFind) and the bounding box of the
// vertices of each piece's faces, indexed by its root.
struct Pieces {
  UnionFind sets;
  std::vector<Vec3> lo, hi;
};
template <class Face>
Pieces FindPieces(const std::vector<Vec3>& V, const std::vector<Face>& F) {
  Pieces p{UnionFind(static_cast<int>(V.size())), std::vector<Vec3>(V.size(), Vec3::Constant(1e300)),
           std::vector<Vec3>(V.size(), Vec3::Constant(-1e300))};
  for (const Face& f : F)
    for (size_t k = 1; k < f.size(); ++k) p.sets.Unite(f[k], f[0]);
  for (const Face& f : F) {
    const int r = p.sets.Find(f[0]);
    for (int v : f) {
      p.lo[size_t(r)] = p.lo[size_t(r)].cwiseMin(V[size_t(v)]);
      p.hi[size_t(r)] = p.hi[size_t(r)].cwiseMax(V[size_t(v)]);
    }
  }
  return p;
}
}  // namespace

SmallPieces FindSmallPieces(const QuadData& cage, double maxDiag) {
  const size_t nV = cage.V.size();
  Pieces pieces = FindPieces(cage.V, cage.F);
  std::vector<long> patches(nV, 0);  // per piece (by its root)
  for (const Quad& q : cage.F) ++patches[size_t(pieces.sets.Find(q[0]))];
  const std::vector<Vec3>&lo = pieces.lo, &hi = pieces.hi;
  SmallPieces s;
  for (size_t r = 0; r < nV; ++r) {
    if (patches[r] == 0) continue;
    ++s.pieces;
    if ((hi[r] - lo[r]).norm() < maxDiag) {
      ++s.small;
      s.smallPatches += patches[r];
    }
  }
  return s;
}

std::string DebrisWarning(const QuadData& cage, double inputDiag) {
  const SmallPieces s = FindSmallPieces(cage, kDebrisDiagPercent / 100.0 * inputDiag);
  if (s.small == 0 || 100.0 * double(s.smallPatches) < kDebrisPatchSharePercent * double(cage.F.size())) return {};
  char buf[600];
  std::snprintf(buf, sizeof buf,
                "%d of the input's %d separate pieces are smaller than %g %% of its diagonal (scan debris?) and hold "
                "%ld of the cage's %zu patches: every piece keeps patches of its own, so a budget below that cannot "
                "be met. Remove them first if they are debris: Filters > Cleaning and Repairing > Remove Isolated "
                "pieces (wrt Diameter) with a diameter of %g %% (PyMeshLab: "
                "meshing_remove_connected_component_by_diameter)",
                s.small, s.pieces, kDebrisDiagPercent, s.smallPatches, cage.F.size(), kDebrisDiagPercent);
  return buf;
}

std::vector<double> PieceDiagonals(const TriData& m) {
  Pieces pieces = FindPieces(m.V, m.F);
  std::vector<double> diag(m.V.size(), 0.0);
  for (const Tri& f : m.F)
    for (int v : f) {
      const int r = pieces.sets.Find(v);
      diag[size_t(v)] = (pieces.hi[size_t(r)] - pieces.lo[size_t(r)]).norm();
    }
  return diag;
}

std::vector<HoleLoop> FindHoleLoops(const TriData& m) {
  // follow each boundary half-edge (a, b) to the one leaving b (at a non-manifold boundary vertex
  // any of them: such a loop is kept, not manifold)
  const std::vector<std::pair<int, int>> half = BoundaryHalfEdges(m);
  if (half.empty()) return {};
  const std::vector<double> pieceDiag = PieceDiagonals(m);
  std::vector<int> next(m.V.size(), -1), out(m.V.size(), 0);
  for (size_t i = 0; i < half.size(); ++i) {
    next[size_t(half[i].first)] = int(i);
    ++out[size_t(half[i].first)];
  }
  std::vector<char> used(half.size(), 0);
  std::vector<HoleLoop> holes;
  for (size_t i = 0; i < half.size(); ++i) {
    if (used[i]) continue;
    HoleLoop h;
    Vec3 lo = m.V[size_t(half[i].first)], hi = lo;
    int last = -1;
    for (int k = int(i); k >= 0 && !used[size_t(k)]; k = next[size_t(half[size_t(k)].second)]) {
      used[size_t(k)] = 1;
      h.vertices.push_back(half[size_t(k)].first);
      h.manifold = h.manifold && out[size_t(half[size_t(k)].first)] == 1;
      last = half[size_t(k)].second;
      lo = lo.cwiseMin(m.V[size_t(last)]);
      hi = hi.cwiseMax(m.V[size_t(last)]);
    }
    h.manifold = h.manifold && last == half[i].first;
    // a loop spanning half its piece or more is the piece's outline (a sheet's rim, a flap that
    // the working copy separated from an edge of three triangles), not a hole in it
    h.diagonal = (hi - lo).norm();
    if (h.diagonal >= kOutlineShare * pieceDiag[size_t(half[i].first)]) continue;
    holes.push_back(std::move(h));
  }
  return holes;
}

SmallHoles FindSmallHoles(const TriData& m, double maxDiag) {
  SmallHoles h;
  for (const HoleLoop& loop : FindHoleLoops(m)) {
    ++h.holes;
    h.small += loop.diagonal < maxDiag;
  }
  return h;
}

std::string HolesWarning(const TriData& input, const QuadData& cage) {
  // the cage's patches with a corner on its boundary (none: the input has no hole, and its own
  // boundary is not searched, a pass over every triangle of a dense scan)
  std::vector<char> onBoundary(cage.V.size(), 0);
  for (const auto& [a, b] : BoundaryHalfEdges(SplitQuads(cage))) onBoundary[size_t(a)] = onBoundary[size_t(b)] = 1;
  long bordering = 0;
  for (const Quad& q : cage.F) bordering += onBoundary[size_t(q[0])] || onBoundary[size_t(q[1])] ||
                                            onBoundary[size_t(q[2])] || onBoundary[size_t(q[3])];
  if (bordering == 0) return {};
  const double patchSide = std::sqrt(TotalArea(input) / double(cage.F.size()));
  const SmallHoles h = FindSmallHoles(input, patchSide);
  if (h.small < kManySmallHoles) return {};
  char buf[800];
  std::snprintf(buf, sizeof buf,
                "%d of the input's %d holes are smaller than the cage's patches (%.3g %% of the diagonal, the side "
                "of an average patch): each stays a hole of the cage, %ld of whose %zu patches border one, and the "
                "limit opens wider than such a hole, so the area around it may be left unreached. If they are gaps "
                "in a scan, let this filter close them for the layout only (the fit still sees them): Close small "
                "holes for the layout (closeHoles) at %.3g %%; or close them in the layer first: Filters > "
                "Remeshing, Simplification and Reconstruction > Close Holes (PyMeshLab: meshing_close_holes)",
                h.small, h.holes, 100 * patchSide / BBoxDiagonal(input.V), bordering, cage.F.size(),
                100 * patchSide / BBoxDiagonal(input.V));
  return buf;
}

namespace {
// The share of `area` (by area) where dist >= 0, and the median of those distances.
SheetShare ShareOf(const std::vector<double>& area, const std::vector<double>& dist) {
  double total = 0, covered = 0;
  std::vector<double> d;
  for (size_t i = 0; i < area.size(); ++i) {
    total += area[i];
    if (dist[i] >= 0 && area[i] > 0) {
      covered += area[i];
      d.push_back(dist[i]);
    }
  }
  SheetShare s;
  s.areaPercent = total > 0 ? 100.0 * (covered / total) : 0.0;  // (a share first: at most 1, so at most 100)
  if (!d.empty()) {
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    s.medianDistance = d[d.size() / 2];
  }
  return s;
}

// +1 when the input's signed volume is positive (faces oriented outwards), else -1. Measured
// from the first vertex (the volume does not depend on the origin; far from it the terms cancel).
double OutwardSign(const TriData& m) {
  const Vec3 o = m.V.empty() ? Vec3::Zero() : m.V[0];
  double vol = 0;
  for (const Tri& f : m.F)
    vol += (m.V[size_t(f[0])] - o).dot((m.V[size_t(f[1])] - o).cross(m.V[size_t(f[2])] - o));
  return vol < 0 ? -1.0 : 1.0;
}
}  // namespace

SecondSheets FindSecondSheets(const TriData& input, const EmbreeScene& scene) {
  SecondSheets w;
  const long nF = long(input.F.size());
  if (nF == 0 || !scene.Ok()) return w;
  const long stride = (nF + kDoubledWallSamples - 1) / kDoubledWallSamples;
  const long n = (nF + stride - 1) / stride;
  const double diag = w.diagonal = BBoxDiagonal(input.V), reach = kDoubledWallDistancePercent / 100.0 * diag;
  const double inward = -OutwardSign(input);  // the side of a face's normal that is inside
  // dist < 0: no second sheet
  std::vector<double> area(size_t(n), 0.0), doubled(size_t(n), -1.0), thin(size_t(n), -1.0);
#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < n; ++i) {
    const Tri& f = input.F[size_t(i * stride)];
    const Vec3 &a = input.V[size_t(f[0])], &b = input.V[size_t(f[1])], &c = input.V[size_t(f[2])];
    const Vec3 cr = (b - a).cross(c - a);
    const double len = cr.norm();
    if (!(len > 0)) continue;
    area[size_t(i)] = 0.5 * len;
    const Vec3 nrm = cr / len, o = (a + b + c) / 3.0;
    for (double side : {1.0, -1.0}) {
      // from just off the triangle itself, so that it is not its own hit
      const EmbreeScene::Hit h = scene.Intersect(o, side * nrm, 1e-6 * diag, reach);
      if (!h.valid || h.face == int(i * stride)) continue;
      const Tri& g = input.F[size_t(h.face)];
      const Vec3 gn = (input.V[size_t(g[1])] - input.V[size_t(g[0])]).cross(input.V[size_t(g[2])] - input.V[size_t(g[0])]);
      if (!(gn.norm() > 0)) continue;
      const double cosine = nrm.dot(gn.normalized());
      double* slot = nullptr;
      if (cosine > kDoubledWallCosine)
        slot = &doubled[size_t(i)];
      else if (cosine < -kDoubledWallCosine && side == inward)
        slot = &thin[size_t(i)];
      if (slot && (*slot < 0 || std::abs(h.t) < *slot)) *slot = std::abs(h.t);
    }
  }
  w.doubled = ShareOf(area, doubled);
  w.thin = ShareOf(area, thin);
  return w;
}

std::string DoubledWallWarning(const SecondSheets& s, const QuadData& cage) {
  if (s.doubled.areaPercent < kDoubledWallAreaPercent) return {};
  char buf[700];
  std::snprintf(buf, sizeof buf,
                "%.0f %% of the input's area has a second sheet facing the same way %.3g %% of the diagonal away "
                "(median): a doubled wall, as two scans of one surface left unmerged make; each sheet gets patches "
                "of its own (the cage has %zu) and the projections can land on the wrong sheet. To fit one "
                "surface, rebuild it from both first: Filters > Remeshing, Simplification and Reconstruction > "
                "Surface Reconstruction: Screened Poisson (PyMeshLab: generate_surface_reconstruction_screened_poisson)",
                s.doubled.areaPercent, 100 * s.doubled.medianDistance / s.diagonal, cage.F.size());
  return buf;
}

std::string ThinSheetWarning(const SecondSheets& s, const QuadData& cage) {
  if (s.thin.areaPercent < kThinSheetAreaPercent) return {};
  char buf[700];
  std::snprintf(buf, sizeof buf,
                "%.0f %% of the input's area is a thin sheet, its other side %.3g %% of the diagonal away (median): "
                "a patch cannot span a rim thinner than itself, so the paper's halting (the M-fitmap test) stops "
                "the collapses early over the whole sheet and the cage has %zu patches, more than its shape needs. "
                "Give a patch budget instead (Target patches; PyMeshLab: targetpatches; run_pipeline.sh --patches N)",
                s.thin.areaPercent, 100 * s.thin.medianDistance / s.diagonal, cage.F.size());
  return buf;
}

}  // namespace vcgext
