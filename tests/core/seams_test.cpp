// Seams (seams.h) closed by the working copy (input_prep.h): separately meshed parts of one
// surface are joined, genuine boundaries are left alone.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "test_support.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/seams.h"

using vcgext::Tri;
using vcgext::TriData;
using vcgext::Vec3;

namespace {
// Directed edges that have no twin: 0 for a closed, consistently oriented mesh.
int UnpairedHalfEdges(const TriData& t) {
  std::multiset<std::pair<int, int>> he;
  for (const Tri& f : t.F)
    for (int k = 0; k < 3; ++k) he.insert({f[k], f[(k + 1) % 3]});
  int n = 0;
  for (const auto& [a, b] : he) n += he.count({b, a}) != 1 || he.count({a, b}) != 1;
  return n;
}
Vec3 Normal(const TriData& t, const Tri& f) { return (t.V[f[1]] - t.V[f[0]]).cross(t.V[f[2]] - t.V[f[0]]) / 2; }
double SignedVolume(const TriData& t) {
  double v = 0;
  for (const Tri& f : t.F) v += t.V[f[0]].dot(t.V[f[1]].cross(t.V[f[2]])) / 6;
  return v;
}
double SmallestArea(const TriData& t) {
  double a = 1e300;
  for (const Tri& f : t.F) a = std::min(a, Normal(t, f).norm());
  return a;
}

// The unit cube's six faces, each gridded on its own (cells[f] x cells[f], vertices not shared
// with the other faces: a CAD body exported face by face), outward, rotated by `rot`, every
// coordinate moved by up to `jitter` (each face computed its own copies of the shared edges'
// points) and rounded to float as MeshLab stores them. Where two faces' grids differ, their
// vertices lie on each other's edges.
TriData SeparatelyGriddedBox(const std::array<int, 6>& cells, const Eigen::Matrix3d& rot, double jitter,
                             std::mt19937& rng) {
  std::uniform_real_distribution<double> off(-jitter, jitter);
  TriData t;
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2, n = cells[size_t(face)];
    const bool plus = face % 2 == 0;
    // tangent axes u, v with u x v along the outward normal
    int u = (axis + 1) % 3, v = (axis + 2) % 3;
    if (!plus) std::swap(u, v);
    const int base = int(t.V.size());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        Vec3 p;
        p[axis] = plus ? 1 : 0;
        p[u] = double(i) / n;
        p[v] = double(j) / n;
        p = rot * p;
        for (int k = 0; k < 3; ++k) p[k] = vcgext::RoundedToFloat(p[k] + (jitter > 0 ? off(rng) : 0.0));
        t.V.push_back(p);
      }
    auto id = [&](int i, int j) { return base + i * (n + 1) + j; };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        t.F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        t.F.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
  }
  return t;
}

// Closed and whole: one component, every edge paired, the cube's volume, no sliver, no vertex moved.
void ExpectClosedBox(const TriData& box, const vcgext::WorkingCopy& w) {
  ASSERT_EQ(w.error, "");
  EXPECT_GT(w.closedTJunctions, 0);
  EXPECT_EQ(w.components, 1);
  EXPECT_EQ(UnpairedHalfEdges(w.mesh), 0);                 // closed: no crack left open
  EXPECT_NEAR(std::abs(SignedVolume(w.mesh)), 1.0, 1e-5);  // the whole cube, nothing doubled
  // no triangle of three collinear vertices: the smallest is a sizeable part of a cell's
  EXPECT_GT(SmallestArea(w.mesh), 1e-6);
  // no vertex moved or added: every working vertex is a layer vertex at its position
  for (size_t v = 0; v < w.mesh.V.size(); ++v) EXPECT_EQ(w.mesh.V[v], box.V[size_t(w.meshToLive[v])]);
  bool named = false;
  for (const std::string& n : w.notes) named |= n.find("T-junction") != std::string::npos;
  EXPECT_TRUE(named);
}
}  // namespace

TEST(Seams, BoxOfSeparatelyGriddedFacesIsClosed) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0, 6.28);
  for (int trial = 0; trial < 12; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const Eigen::Matrix3d rot =
        trial == 0 ? Eigen::Matrix3d::Identity()
                   : (Eigen::AngleAxisd(angle(rng), Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(angle(rng), Vec3::UnitX()))
                         .toRotationMatrix();
    std::array<int, 6> cells;
    for (int& c : cells) c = 3 + int(rng() % 9);
    // odd trials: every face with its own copies of the shared points, 3e-7 apart (the tolerance
    // is 1e-6 of the diagonal, 1.7e-6): welded at the seams as well
    const double jitter = trial % 2 ? 3e-7 : 0;
    const TriData box = SeparatelyGriddedBox(cells, rot, jitter, rng);
    const vcgext::WorkingCopy w = vcgext::PrepareWorkingCopy(box);
    ExpectClosedBox(box, w);
    if (jitter > 0) {
      EXPECT_EQ(w.mergedVertices, 0);  // no exact duplicates left to merge
      EXPECT_GT(w.seamVertices, 0);
    }
  }
}

// One triangle with vertices inserted into all three sides: the pieces tile it exactly (same
// area, same orientation, none of zero area) and use every inserted vertex.
TEST(Seams, FaceWithVerticesOnEverySideIsTiledWithoutSlivers) {
  TriData t;
  t.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  t.F = {{0, 1, 2}};
  // neighbours' boundary faces whose corners lie on the triangle's sides (each a separate face
  // below the plane, so that their own edges are boundary too)
  const std::vector<Vec3> onSides = {{0.3, 0, 0}, {0.6, 0, 0}, {0.5, 0.5, 0}, {0, 0.7, 0}, {0, 0.2, 0}};
  for (const Vec3& p : onSides) {
    const int a = int(t.V.size());
    t.V.push_back(p);
    t.V.push_back(p + Vec3(0, 0, -1));
    t.V.push_back(p + Vec3(-1, -1, -1));
    t.F.push_back({a, a + 1, a + 2});
  }
  std::vector<int> boundary;
  for (int s = 0; s < int(t.F.size()) * 3; ++s) boundary.push_back(s);
  TriData out = t;
  EXPECT_EQ(vcgext::CloseTJunctions(t.V, out.F, boundary, 1e-9), 5);
  double area = 0;
  std::set<int> used;
  for (const Tri& f : out.F) {
    const Vec3 n = Normal(out, f);
    if (n.z() == 0) continue;  // a neighbour (vertical)
    EXPECT_GT(n.z(), 1e-3) << f[0] << " " << f[1] << " " << f[2];
    area += n.z();
    used.insert(f.begin(), f.end());
  }
  EXPECT_NEAR(area, 0.5, 1e-12);
  EXPECT_EQ(used.size(), 8u);  // 3 corners + 5 inserted
}

// Boundaries that are not T-junctions stay: a sphere's holes, a vertex 10 tolerances off an edge.
TEST(Seams, GenuineBoundariesAreLeftAlone) {
  const TriData holes = testsupport::SphereWithHoles(10);
  const vcgext::WorkingCopy w = vcgext::PrepareWorkingCopy(holes);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.closedTJunctions, 0);
  EXPECT_EQ(w.mesh.F.size(), holes.F.size());

  TriData t;
  t.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, -1e-5, 0}, {0.5, -1, 0}, {1.5, -1, 0}};
  t.F = {{0, 1, 2}, {3, 4, 5}};
  std::vector<int> boundary = {0, 1, 2, 3, 4, 5};
  TriData out = t;
  EXPECT_EQ(vcgext::CloseTJunctions(t.V, out.F, boundary, 1e-6), 0);
  EXPECT_EQ(out.F, t.F);
  EXPECT_EQ(vcgext::CloseTJunctions(t.V, out.F, boundary, 1e-4), 1);  // within tolerance: inserted
  EXPECT_EQ(out.F.size(), 3u);
}

namespace {
// A 20 x 20 grid of the unit square (cells 0.05) whose right half has its own copies of the
// vertices on x = 0.5, raised by `gap` (a crack along the middle, 21 vertices on each side).
TriData CrackedGrid(double gap) {
  const int n = 20, half = 10;
  TriData t;
  auto id = [&](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) t.V.push_back(Vec3(double(i) / n, double(j) / n, 0));
  std::vector<int> copy(size_t(n + 1));
  for (int j = 0; j <= n; ++j) {
    copy[size_t(j)] = int(t.V.size());
    t.V.push_back(Vec3(0.5, double(j) / n, gap));
  }
  auto at = [&](int i, int j) { return i == half ? copy[size_t(j)] : id(i, j); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      auto v = [&](int a, int b) { return a == half && i >= half ? at(a, b) : id(a, b); };
      t.F.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      t.F.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  return t;
}
bool Warned(const vcgext::WorkingCopy& w, const std::string& what) {
  for (const std::string& s : w.warnings)
    if (s.find(what) != std::string::npos) return true;
  return false;
}
}  // namespace

// A crack wider than the seam weld (a millionth of the diagonal) but far narrower than the edges
// beside it is counted (both sides' 21 vertices), warned about with a merging distance that
// closes it and stays below the edges, and left open (the vertex count unchanged); one within
// the weld is welded and not warned about; one a fifth of an edge wide is a slit, not a crack;
// coincident boundary vertices (kept apart when merging them would pinch the surface) are not
// counted.
TEST(Seams, CracksWiderThanTheWeldAreWarnedAboutNotWelded) {
  const TriData cracked = CrackedGrid(1e-4);
  const vcgext::WorkingCopy w = vcgext::PrepareWorkingCopy(cracked);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.crackVertices, 42);
  EXPECT_EQ(w.mesh.V.size(), cracked.V.size());
  ASSERT_TRUE(Warned(w, "42 boundary vertices lie near another boundary's")) << ::testing::PrintToString(w.warnings);
  ASSERT_TRUE(Warned(w, "Merge Close Vertices with a merging distance of 0.00015 "))
      << ::testing::PrintToString(w.warnings);

  const vcgext::WorkingCopy welded = vcgext::PrepareWorkingCopy(CrackedGrid(1e-7));
  EXPECT_EQ(welded.seamVertices, 21);
  EXPECT_EQ(welded.crackVertices, 0);
  EXPECT_TRUE(welded.warnings.empty());
  const vcgext::WorkingCopy slit = vcgext::PrepareWorkingCopy(CrackedGrid(0.01));
  EXPECT_EQ(slit.crackVertices, 0);
  EXPECT_TRUE(slit.warnings.empty());

  // two triangles touching at coincident copies of a corner: not a crack
  const std::vector<Vec3> V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {-1, 0, 0}, {0, -1, 0}};
  const std::vector<Tri> F = {{0, 1, 2}, {3, 4, 5}};
  double reach = 0, widest = 0;
  EXPECT_EQ(vcgext::NearBoundaryVertices(V, F, {0, 1, 2, 3, 4, 5}, 0.1, reach, widest), 0);
  EXPECT_EQ(widest, 0.0);
  // boundary edges 1e-14 of the extent (the fuzzer's crack_grid_below_the_extent): gaps that small
  // are the seam weld's, and no grid is built with cells below VertexGrid's limit
  const std::vector<Vec3> tiny = {{0, 0, 0}, {1e-14, 0, 0}, {0, 1e-14, 0}, {1, 1, 1}, {1 + 1e-14, 1, 1}, {1, 1 + 1e-14, 1}};
  EXPECT_EQ(vcgext::NearBoundaryVertices(tiny, F, {0, 1, 2, 3, 4, 5}, 0.1, reach, widest), 0);
  EXPECT_EQ(reach, 0.0);
}
