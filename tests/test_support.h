#pragma once
/// Shared test helpers: sample-scan paths, analytic meshes, conversions.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/mesh_types.h"

namespace testsupport {

/// Absolute path of a libcgal-demo sample mesh (e.g. "bunny00.off"); fails the test if missing.
std::string SamplePath(const std::string& name);
/// Loads a sample mesh as arrays (ASSERTs inside on failure).
vcgext::TriData LoadSample(const std::string& name);
/// A regular nx × ny grid of the unit square [0,1]^2 at z = 0 (2·nx·ny triangles), scaled by `size`.
vcgext::TriData PlaneGrid(int nx, int ny, double size = 1.0);
/// Height field z = f(x, y) over [0,size]^2 sampled on an nx × ny grid.
template <class F>
vcgext::TriData HeightField(int nx, int ny, double size, F f) {
  vcgext::TriData m = PlaneGrid(nx, ny, size);
  for (auto& p : m.V) p[2] = f(p[0], p[1]);
  return m;
}
/// A 64 x 64 grid of the unit square (8 192 triangles), flat for x < 0.5 and z = 0.4 (x - 0.5)^2
/// beyond, with `n` (<= 5) zero-area faces in the flat half: in face (a, c, b) of cell (i, j), with
/// c = (i+1, j) and b = (i+1, j+1), c is moved to the middle of the diagonal a b (exactly:
/// coordinates in 1/128, exact in float too) or, with `coincident`, onto a. Neither folds a
/// neighbouring face. (Dense scans' float-rounded slivers: docs/robustness.md.)
vcgext::TriData GridWithZeroAreaFaces(int n, bool coincident = false);
/// Icosphere of radius r with `level` 1:4 subdivisions (20·4^level triangles).
vcgext::TriData Icosphere(int level, double r = 1.0);
/// Icosphere(4) (2 562 vertices, edges of about 0.075) with the one-rings of k vertices at least
/// 0.3 apart removed: k holes of about 0.15 across (the corpus's scan_holes.off has 30).
vcgext::TriData SphereWithHoles(int k);
/// Mesh m with every `every`-th face (from every/2 on) deleted where no hole made before shares
/// one of its corners: one-triangle holes that share no vertex, so the mesh stays manifold (a holed
/// scan; elephant.off at 50: ~2 % of the faces, as the breakage runs' holed variants).
vcgext::TriData WithIsolatedHoles(const vcgext::TriData& m, int every);
/// UV sphere: n longitudes, m latitude bands, one vertex per pole (valence n), outward faces.
vcgext::TriData UvSphere(int n, int m);
/// A face's corner cycle rotated so that its smallest index comes first (orientation kept): equal
/// for two faces exactly when they are the same oriented face. Works on std::array and std::vector.
template <class Cycle = std::vector<int>>
Cycle CanonicalCycle(Cycle c) {
  std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
  return c;
}
/// The faces as a set of canonical cycles: equal for two face lists with the same oriented faces
/// in any order and at any starting corner.
template <class Faces>
std::set<typename Faces::value_type> CanonicalFaceSet(const Faces& faces) {
  std::set<typename Faces::value_type> s;
  for (const auto& f : faces) s.insert(CanonicalCycle(f));
  return s;
}
/// Arrays -> vcg mesh (for testing the templated vcg entry points).
void ToVcg(const vcgext::TriData& d, vcgext::TMesh& m);
/// A scratch directory unique to this test process.
std::string ScratchDir();

}  // namespace testsupport
