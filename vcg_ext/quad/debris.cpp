/// \file debris.cpp
/// Small separate pieces of a cage (debris.h).
#include "vcg_ext/quad/debris.h"

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace vcgext {

namespace {
int Root(std::vector<int>& parent, int x) {
  while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
  return x;
}
}  // namespace

SmallPieces FindSmallPieces(const QuadData& cage, double maxDiag) {
  const size_t nV = cage.V.size();
  std::vector<int> parent(nV);
  std::iota(parent.begin(), parent.end(), 0);
  for (const Quad& q : cage.F)
    for (int k = 1; k < 4; ++k) parent[size_t(Root(parent, q[k]))] = Root(parent, q[0]);
  // per piece (by its root): bounding box and patches
  std::vector<Vec3> lo(nV, Vec3::Constant(1e300)), hi(nV, Vec3::Constant(-1e300));
  std::vector<long> patches(nV, 0);
  for (const Quad& q : cage.F) {
    const int r = Root(parent, q[0]);
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

}  // namespace vcgext
