/// \file scan_artifacts.cpp
/// Debris and small holes of a raw scan, and what they cost the cage (scan_artifacts.h).
#include "vcg_ext/quad/scan_artifacts.h"

#include "vcg_ext/core/union_find.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vcgext {

SmallPieces FindSmallPieces(const QuadData& cage, double maxDiag) {
  const size_t nV = cage.V.size();
  UnionFind pieces(static_cast<int>(nV));
  for (const Quad& q : cage.F)
    for (int k = 1; k < 4; ++k) pieces.Unite(q[k], q[0]);
  // per piece (by its root): bounding box and patches
  std::vector<Vec3> lo(nV, Vec3::Constant(1e300)), hi(nV, Vec3::Constant(-1e300));
  std::vector<long> patches(nV, 0);
  for (const Quad& q : cage.F) {
    const int r = pieces.Find(q[0]);
    ++patches[size_t(r)];
    for (int v : q) {
      lo[size_t(r)] = lo[size_t(r)].cwiseMin(cage.V[size_t(v)]);
      hi[size_t(r)] = hi[size_t(r)].cwiseMax(cage.V[size_t(v)]);
    }
  }
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

namespace {
// Bounding-box diagonal of each vertex's piece (faces joined at shared vertices), by vertex.
std::vector<double> PieceDiagonals(const TriData& m) {
  UnionFind pieces(static_cast<int>(m.V.size()));
  for (const Tri& f : m.F) {
    pieces.Unite(f[1], f[0]);
    pieces.Unite(f[2], f[0]);
  }
  std::vector<Vec3> lo(m.V.size(), Vec3::Constant(1e300)), hi(m.V.size(), Vec3::Constant(-1e300));
  for (int v = 0; v < int(m.V.size()); ++v) {
    const int r = pieces.Find(v);
    lo[size_t(r)] = lo[size_t(r)].cwiseMin(m.V[size_t(v)]);
    hi[size_t(r)] = hi[size_t(r)].cwiseMax(m.V[size_t(v)]);
  }
  std::vector<double> diag(m.V.size());
  for (int v = 0; v < int(m.V.size()); ++v) {
    const int r = pieces.Find(v);
    diag[size_t(v)] = (hi[size_t(r)] - lo[size_t(r)]).norm();
  }
  return diag;
}
}  // namespace

SmallHoles FindSmallHoles(const TriData& m, double maxDiag) {
  // follow each boundary half-edge (a, b) to the one leaving b (at a non-manifold boundary vertex
  // any of them: the loops' count and sizes are what matters here)
  const std::vector<std::pair<int, int>> half = BoundaryHalfEdges(m);
  if (half.empty()) return {};
  const std::vector<double> pieceDiag = PieceDiagonals(m);
  std::vector<int> next(m.V.size(), -1);
  for (size_t i = 0; i < half.size(); ++i) next[size_t(half[i].first)] = int(i);
  std::vector<char> used(half.size(), 0);
  SmallHoles h;
  for (size_t i = 0; i < half.size(); ++i) {
    if (used[i]) continue;
    Vec3 lo = m.V[size_t(half[i].first)], hi = lo;
    for (int k = int(i); k >= 0 && !used[size_t(k)]; k = next[size_t(half[size_t(k)].second)]) {
      used[size_t(k)] = 1;
      lo = lo.cwiseMin(m.V[size_t(half[size_t(k)].second)]);
      hi = hi.cwiseMax(m.V[size_t(half[size_t(k)].second)]);
    }
    // a loop spanning half its piece or more is the piece's outline (a sheet's rim, a flap that
    // the working copy separated from an edge of three triangles), not a hole in it
    const double d = (hi - lo).norm();
    if (d >= kOutlineShare * pieceDiag[size_t(half[i].first)]) continue;
    ++h.holes;
    h.small += d < maxDiag;
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
  char buf[600];
  std::snprintf(buf, sizeof buf,
                "%d of the input's %d holes are smaller than the cage's patches (%.3g %% of the diagonal, the side "
                "of an average patch): each stays a hole of the cage, %ld of whose %zu patches border one, and the "
                "limit opens wider than such a hole, so the area around it may be left unreached. If they are gaps "
                "in a scan, close them first: Filters > Remeshing, Simplification and Reconstruction > Close Holes "
                "(PyMeshLab: meshing_close_holes)",
                h.small, h.holes, 100 * patchSide / BBoxDiagonal(input.V), bordering, cage.F.size());
  return buf;
}

}  // namespace vcgext
