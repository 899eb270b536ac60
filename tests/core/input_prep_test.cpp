// The working copy every filter runs on (input_prep.h, issue 16): exact repairs, clear errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "test_support.h"
#include "vcg_ext/core/input_prep.h"

using vcgext::TriData;
using vcgext::Vec3;
using vcgext::WorkingCopy;

namespace {
// Every edge in two faces, traversed once each way (closed, consistently oriented).
bool ClosedAndOriented(const TriData& t) {
  std::multiset<std::pair<int, int>> he;
  for (const auto& f : t.F)
    for (int k = 0; k < 3; ++k) he.insert({f[k], f[(k + 1) % 3]});
  for (const auto& [a, b] : he)
    if (he.count({a, b}) != 1 || he.count({b, a}) != 1) return false;
  return true;
}
double SignedVolume(const TriData& t) {
  double v = 0;
  for (const auto& f : t.F) v += t.V[f[0]].dot(t.V[f[1]].cross(t.V[f[2]])) / 6;
  return v;
}
// A strip of n quads (2n triangles) closed into a loop, with a half twist if `mobius`.
TriData Strip(int n, bool mobius) {
  TriData t;
  for (int i = 0; i < n; ++i) {
    double a = 2 * M_PI * i / n, tw = mobius ? a / 2 : 0;
    Vec3 c(3 * std::cos(a), 3 * std::sin(a), 0), r(std::cos(a), std::sin(a), 0);
    Vec3 d = std::cos(tw) * r + std::sin(tw) * Vec3(0, 0, 1);
    t.V.push_back(c - 0.5 * d);
    t.V.push_back(c + 0.5 * d);
  }
  for (int i = 0; i < n; ++i) {
    int a = 2 * i, b = 2 * i + 1, c = 2 * ((i + 1) % n), d = c + 1;
    if (mobius && i == n - 1) std::swap(c, d);  // the half twist joins the sides crosswise
    t.F.push_back({a, c, d});
    t.F.push_back({a, d, b});
  }
  return t;
}
}  // namespace

TEST(InputPrep, CleanMeshIsUnchanged) {
  TriData s = testsupport::Icosphere(2);
  WorkingCopy w = vcgext::PrepareWorkingCopy(s);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.mesh.V, s.V);
  EXPECT_EQ(w.mesh.F, s.F);
  EXPECT_TRUE(w.notes.empty());
  EXPECT_TRUE(w.warnings.empty());
  EXPECT_EQ(w.components, 1);
}

TEST(InputPrep, SoupIsWeldedToTheSameMesh) {
  TriData s = testsupport::Icosphere(2), soup;
  for (const auto& f : s.F) {
    for (int k = 0; k < 3; ++k) soup.V.push_back(s.V[f[k]]);
    int b = int(soup.V.size()) - 3;
    soup.F.push_back({b, b + 1, b + 2});
  }
  WorkingCopy w = vcgext::PrepareWorkingCopy(soup);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.mesh.V.size(), s.V.size());
  EXPECT_EQ(w.mergedVertices, int(soup.V.size() - s.V.size()));
  EXPECT_TRUE(ClosedAndOriented(w.mesh));
  for (size_t i = 0; i < soup.V.size(); ++i) EXPECT_EQ(w.mesh.V[w.liveToMesh[i]], soup.V[i]);
  ASSERT_EQ(w.notes.size(), 1u);
  EXPECT_NE(w.notes[0].find("merged"), std::string::npos);
}

namespace {
// A triangle soup of `t` (each face with its own three vertices), each coordinate moved by up to
// `jitter` (uniform): an export that rounded every face's corners on their own.
TriData RoundedSoup(const TriData& t, double jitter, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  TriData soup;
  for (const auto& f : t.F) {
    for (int k = 0; k < 3; ++k) soup.V.push_back(t.V[f[k]] + Vec3(u(rng), u(rng), u(rng)));
    const int b = int(soup.V.size()) - 3;
    soup.F.push_back({b, b + 1, b + 2});
  }
  return soup;
}
}  // namespace

// An unwelded soup whose copies of a vertex differ by rounding (1e-8 of the diagonal, 1e-6 the
// tolerance) is welded back into the mesh; one moved farther (1e-4) is not, nor are separate
// triangles far apart (particles), which only the exact merge would join.
TEST(InputPrep, SoupWithRoundedCoordinatesIsWeldedWithinAMillionthOfTheDiagonal) {
  const TriData s = testsupport::Icosphere(2);  // diagonal 2 sqrt(3) (radius 1)
  const TriData soup = RoundedSoup(s, 1e-8, 3);
  WorkingCopy w = vcgext::PrepareWorkingCopy(soup);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.mesh.V.size(), s.V.size());
  EXPECT_EQ(w.mesh.F.size(), s.F.size());
  EXPECT_EQ(w.mergedVertices, 0);
  EXPECT_EQ(w.weldedVertices, int(soup.V.size() - s.V.size()));
  EXPECT_EQ(w.components, 1);
  EXPECT_TRUE(ClosedAndOriented(w.mesh));
  for (size_t i = 0; i < soup.V.size(); ++i) EXPECT_LT((w.mesh.V[w.liveToMesh[i]] - soup.V[i]).norm(), 1e-7);
  ASSERT_EQ(w.notes.size(), 1u);
  EXPECT_NE(w.notes[0].find("welded " + std::to_string(soup.V.size() - s.V.size()) + " vertices"), std::string::npos)
      << w.notes[0];

  const WorkingCopy far = vcgext::PrepareWorkingCopy(RoundedSoup(s, 1e-4, 3));
  ASSERT_EQ(far.error, "");
  EXPECT_EQ(far.weldedVertices, 0);
  EXPECT_EQ(far.components, int(s.F.size()));

  TriData particles;
  for (int k = 0; k < 100; ++k) {
    const Vec3 c(0.1 * (k % 10), 0.1 * (k / 10), 0);
    particles.V.insert(particles.V.end(), {c, c + Vec3(0.01, 0, 0), c + Vec3(0, 0.01, 0)});
    particles.F.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  }
  const WorkingCopy p = vcgext::PrepareWorkingCopy(particles);
  ASSERT_EQ(p.error, "");
  EXPECT_EQ(p.weldedVertices, 0);
  EXPECT_EQ(p.components, 100);
}

// An STL soup (exact duplicates) of two tetrahedra touching at a point: merged, the point is a
// non-manifold vertex and is split; kept apart (what coincident vertices that must stay apart get,
// below) the soup would stay eight separate triangles.
TEST(InputPrep, StlSoupOfPartsTouchingAtAPointIsWeldedAndSplitNotLeftApart) {
  TriData t;
  t.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  t.F = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}};
  const WorkingCopy w = vcgext::PrepareWorkingCopy(RoundedSoup(t, 0, 1));
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.mergedVertices, 24 - 7);
  EXPECT_EQ(w.splitVertices, 1);
  EXPECT_EQ(w.components, 2);
  EXPECT_EQ(w.mesh.V.size(), 8u);
  EXPECT_TRUE(ClosedAndOriented(w.mesh));
}

TEST(InputPrep, InconsistentOrientationIsRepairedByMajority) {
  TriData s = testsupport::Icosphere(2);
  const double vol = SignedVolume(s);
  TriData bad = s;
  int flipped = 0;
  for (size_t f = 0; f < bad.F.size(); f += 4, ++flipped) std::swap(bad.F[f][1], bad.F[f][2]);
  WorkingCopy w = vcgext::PrepareWorkingCopy(bad);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.flippedFaces, flipped);
  EXPECT_TRUE(ClosedAndOriented(w.mesh));
  EXPECT_NEAR(SignedVolume(w.mesh), vol, 1e-12);  // the majority (outward) orientation kept
}

TEST(InputPrep, UnreferencedDegenerateAndRepeatedAreLeftOut) {
  TriData s = testsupport::PlaneGrid(4, 4);
  TriData bad = s;
  bad.V.push_back(Vec3(100, 100, 100));         // stray vertex
  bad.F.push_back({0, 0, 1});                   // degenerate
  bad.F.push_back(s.F[3]);                      // repeated
  bad.F.push_back({s.F[5][0], s.F[5][2], s.F[5][1]});  // repeated, other orientation
  WorkingCopy w = vcgext::PrepareWorkingCopy(bad);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.unreferencedVertices, 1);
  EXPECT_EQ(w.degenerateFaces, 1);
  EXPECT_EQ(w.duplicateFaces, 2);
  EXPECT_EQ(w.mesh.F.size(), s.F.size());
  EXPECT_EQ(w.mesh.V.size(), s.V.size());
  EXPECT_EQ(w.liveToMesh.back(), -1);
  EXPECT_EQ(w.notes.size(), 3u);
}

TEST(InputPrep, MobiusStripIsAClearError) {
  EXPECT_EQ(vcgext::PrepareWorkingCopy(Strip(12, false)).error, "");
  WorkingCopy w = vcgext::PrepareWorkingCopy(Strip(12, true));
  EXPECT_EQ(w.nonOrientableComponents, 1);
  EXPECT_NE(w.error.find("not orientable"), std::string::npos) << w.error;
}

namespace {
// Brute force, std::map based: edges in more than two faces; vertices whose faces form more
// than one fan joined across edges of exactly two faces.
std::pair<int, int> BruteForceNonManifold(const TriData& t) {
  std::map<std::pair<int, int>, std::vector<int>> edge;
  for (int f = 0; f < int(t.F.size()); ++f)
    for (int k = 0; k < 3; ++k) edge[std::minmax(t.F[f][k], t.F[f][(k + 1) % 3])].push_back(f);
  int edges = 0, vertices = 0;
  for (const auto& [key, fs] : edge) edges += fs.size() > 2;
  for (int v = 0; v < int(t.V.size()); ++v) {
    std::map<int, int> parent;  // union-find over the faces at v
    for (int f = 0; f < int(t.F.size()); ++f)
      if (std::count(t.F[f].begin(), t.F[f].end(), v)) parent[f] = f;
    std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
    for (const auto& [key, fs] : edge)
      if ((key.first == v || key.second == v) && fs.size() == 2) parent[find(fs[0])] = find(fs[1]);
    int roots = 0;
    for (const auto& [f, p] : parent) roots += find(f) == f;
    vertices += roots > 1;
  }
  return {edges, vertices};
}
}  // namespace

namespace {
// Boundary half-edges of the working copy between vertices the split did not copy (the sheet
// keeps the originals: it holds the vertices' first faces) that lie on the grid's plane z = 0
// strictly inside the unit square: a slit of the sheet (its own boundary is on the square's sides).
int InteriorBoundaryEdgesOnSheet(const WorkingCopy& w) {
  const TriData& m = w.mesh;
  auto original = [&](int v) { return w.liveToMesh[size_t(w.meshToLive[size_t(v)])] == v; };
  int n = 0;
  for (const auto& [a, b] : vcgext::BoundaryHalfEdges(m)) {
    if (!original(a) || !original(b)) continue;
    const Vec3 mid = 0.5 * (m.V[a] + m.V[b]);
    n += std::abs(mid.z()) < 1e-12 && mid.x() > 1e-9 && mid.x() < 1 - 1e-9 && mid.y() > 1e-9 && mid.y() < 1 - 1e-9;
  }
  return n;
}
}  // namespace

// Edges of three or more triangles: the two triangles that continue each other most smoothly keep
// the edge, the others come off it with their fans (their own copies of its vertices), and nothing
// is deleted. A fin on a sheet, a wall standing on a chain of the sheet's edges (the sheet is not
// slit along it), a fin with a bow-tie elsewhere, and a closed tetrahedron with a flap continuing
// one of its faces (the smooth pair would be the flap and that face, which leaves the edge with
// three triangles: every triangle comes off instead). Each result is manifold by the brute force.
TEST(InputPrep, TrianglesOnNonManifoldEdgesAreSeparated) {
  TriData fin = testsupport::PlaneGrid(2, 1);  // 4 triangles; add a fin on the middle edge
  fin.V.push_back(Vec3(0.5, 0.5, 1));
  const int top = int(fin.V.size()) - 1;
  // the shared interior diagonal or edge of the grid: find an edge used twice
  std::multiset<std::pair<int, int>> e;
  for (const auto& f : fin.F)
    for (int k = 0; k < 3; ++k) e.insert(std::minmax(f[k], f[(k + 1) % 3]));
  std::pair<int, int> shared{-1, -1};
  for (const auto& x : e)
    if (e.count(x) == 2) { shared = x; break; }
  ASSERT_GE(shared.first, 0);
  fin.F.push_back({shared.first, shared.second, top});
  WorkingCopy w = vcgext::PrepareWorkingCopy(fin);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.nonManifoldEdges, 1);
  EXPECT_EQ(w.separatedEdges, 1);
  EXPECT_EQ(w.nonManifoldVertices, 2);  // the edge's ends: the sheet's fan and the fin's
  EXPECT_EQ(w.splitVertices, 2);
  EXPECT_EQ(w.components, 2);           // the sheet and the fin
  EXPECT_EQ(w.mesh.F.size(), fin.F.size());
  EXPECT_EQ(BruteForceNonManifold(w.mesh), std::make_pair(0, 0));
  EXPECT_EQ(InteriorBoundaryEdgesOnSheet(w), 0);
  ASSERT_FALSE(w.notes.empty());
  EXPECT_NE(w.notes[0].find("separated the triangles on 1 edge shared by more than two"), std::string::npos)
      << w.notes[0];

  // a wall of 2 x 4 triangles standing on the sheet's row of edges y = 0.5
  TriData wall = testsupport::PlaneGrid(4, 2);
  const int nGrid = int(wall.V.size());
  for (int i = 0; i <= 4; ++i) wall.V.push_back(Vec3(0.25 * i, 0.5, 0.5));
  for (int i = 0; i < 4; ++i) {
    const int a = 5 + i, b = 5 + i + 1, c = nGrid + i, d = nGrid + i + 1;  // grid row j = 1: 5..9
    wall.F.push_back({a, b, d});
    wall.F.push_back({a, d, c});
  }
  w = vcgext::PrepareWorkingCopy(wall);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.separatedEdges, 4);
  EXPECT_EQ(w.components, 2);
  EXPECT_EQ(BruteForceNonManifold(w.mesh), std::make_pair(0, 0));
  EXPECT_EQ(InteriorBoundaryEdgesOnSheet(w), 0);  // the sheet stays whole under the wall

  // a fin and a bow-tie: both repaired, one note each
  TriData both = fin;
  // (off the sheet's plane: a triangle lying along the sheet's rim would meet it at T-junctions)
  both.V.push_back(Vec3(-3, -1, 1));
  both.V.push_back(Vec3(-3, -2, 1));
  int corner = 0;  // a grid vertex away from the fin
  while (corner == shared.first || corner == shared.second) ++corner;
  both.F.push_back({corner, int(both.V.size()) - 2, int(both.V.size()) - 1});
  w = vcgext::PrepareWorkingCopy(both);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.nonManifoldEdges, 1);
  EXPECT_EQ(w.nonManifoldVertices, 3);
  EXPECT_EQ(w.components, 3);
  EXPECT_EQ(BruteForceNonManifold(w.mesh), std::make_pair(0, 0));
  EXPECT_EQ(w.notes.size(), 2u);

  // a closed tetrahedron with a flap in the plane of its face (0, 1, 2), continuing it across edge 1-2
  TriData tet;
  tet.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}};
  tet.F = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}, {2, 4, 1}};
  w = vcgext::PrepareWorkingCopy(tet);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.separatedEdges, 1);
  EXPECT_EQ(w.components, 2);  // the closed tetrahedron and the flap
  EXPECT_EQ(w.mesh.F.size(), 5u);
  EXPECT_EQ(BruteForceNonManifold(w.mesh), std::make_pair(0, 0));
  EXPECT_TRUE(vcgext::BoundaryHalfEdges(w.mesh).size() == 3u);  // the flap's three sides only
}

// A bow-tie (two triangles touching at one vertex) is split, as MeshLab's Repair non Manifold
// Vertices does: the shared vertex gets a copy for the second triangle, both at its position and
// both mapped to it, so per-vertex results go back to the layer's vertex.
TEST(InputPrep, NonManifoldVerticesAreSplitIntoOneCopyPerSheet) {
  TriData bowtie;
  bowtie.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  bowtie.F = {{0, 1, 2}, {0, 3, 4}};
  WorkingCopy w = vcgext::PrepareWorkingCopy(bowtie);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.nonManifoldEdges, 0);
  EXPECT_EQ(w.nonManifoldVertices, 1);
  EXPECT_EQ(w.splitVertices, 1);
  ASSERT_EQ(w.mesh.V.size(), 6u);
  ASSERT_EQ(w.mesh.F.size(), 2u);
  EXPECT_EQ(w.meshToLive[5], 0);                 // the copy stands for the layer's vertex 0
  EXPECT_EQ(w.mesh.V[5], bowtie.V[0]);
  EXPECT_EQ(w.liveToMesh[0], 0);                 // which keeps the first sheet's vertex
  EXPECT_EQ(w.mesh.F[0][0], 0);
  EXPECT_EQ(w.mesh.F[1][0], 5);                  // the second sheet uses the copy
  ASSERT_FALSE(w.notes.empty());
  EXPECT_NE(w.notes[0].find("split 1 vertex where separate pieces of surface touch"), std::string::npos) << w.notes[0];
  EXPECT_EQ(vcgext::ToLiveVertices(w, std::vector<int>{7, 1, 2, 3, 4, 8}, -1), (std::vector<int>{7, 1, 2, 3, 4}));
  std::vector<vcgext::Quad> quads{{0, 1, 2, 3}};
  EXPECT_FALSE(vcgext::RemapQuadsToWorkingCopy(w, quads));  // a corner could be either copy
}


// Quads whose triangles the working copy re-oriented are usable when they run as its triangles do
// (read oriented, as ImportQuads' `flipped` gives them), and refused as stored (reversed against the
// faces made of them): each quad side must be a side of a working triangle, the same way round.
TEST(InputPrep, QuadsAreRemappedWhenTheyRunAsTheOrientedTriangles) {
  TriData grid;
  std::vector<vcgext::Quad> quads;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) grid.V.push_back(Vec3(i, j, 0.1 * ((i * j) % 3)));
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = 4 * j + i;
      quads.push_back({a, a + 1, a + 5, a + 4});
    }
  std::vector<vcgext::Quad> stored = quads;
  std::reverse(stored[4].begin(), stored[4].end());  // the middle quad stored clockwise
  for (const auto& q : stored) {
    grid.F.push_back({q[0], q[1], q[2]});
    grid.F.push_back({q[0], q[2], q[3]});
  }
  WorkingCopy w = vcgext::PrepareWorkingCopy(grid);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.flippedFaces, 2);
  // as stored: the middle quad's sides are all inner edges, each run that way by a neighbour's
  // triangle, but not by its own
  EXPECT_FALSE(vcgext::RemapQuadsToWorkingCopy(w, stored));
  std::vector<vcgext::Quad> oriented = quads;
  ASSERT_TRUE(vcgext::RemapQuadsToWorkingCopy(w, oriented));
  for (size_t f = 0; f < quads.size(); ++f)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(oriented[f][k], w.liveToMesh[quads[f][k]]);
  std::vector<vcgext::Quad> missing = quads;
  missing[0] = {0, 1, 6, 4};  // a side (1, 6) no working triangle has
  EXPECT_FALSE(vcgext::RemapQuadsToWorkingCopy(w, missing));
}

// The counts on random damage (fins on random edges, triangles hung on random vertices) against
// the brute force, and unchanged by renumbering the vertices and reordering the faces.
TEST(InputPrep, NonManifoldCountsMatchBruteForceOnRandomDamage) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 12; ++trial) {
    TriData t = testsupport::Icosphere(1);  // 80 triangles, 42 vertices
    std::uniform_int_distribution<int> F(0, int(t.F.size()) - 1), V(0, 41), K(0, 2);
    const int fins = trial % 4, hung = trial / 4;
    for (int i = 0; i < fins; ++i) {
      const auto& f = t.F[F(rng)];
      const int k = K(rng);
      t.V.push_back(Vec3(0.1 * i, 2, 0.1 * trial));
      t.F.push_back({f[k], f[(k + 1) % 3], int(t.V.size()) - 1});
    }
    for (int i = 0; i < hung; ++i) {
      t.V.push_back(Vec3(3, 0.1 * i, 0));
      t.V.push_back(Vec3(3, 0.1 * i, 1));
      t.F.push_back({V(rng), int(t.V.size()) - 2, int(t.V.size()) - 1});
    }
    const auto [edges, vertices] = BruteForceNonManifold(t);
    EXPECT_EQ(edges > 0 || vertices > 0, fins + hung > 0);
    WorkingCopy w = vcgext::PrepareWorkingCopy(t);
    EXPECT_EQ(w.nonManifoldEdges, edges) << "trial " << trial;
    EXPECT_EQ(w.nonManifoldVertices, vertices) << "trial " << trial;
    // fins separated and vertices split: a manifold copy of the same faces, each vertex where its
    // layer vertex is
    ASSERT_EQ(w.error, "") << "trial " << trial;
    EXPECT_EQ(w.separatedEdges, edges) << "trial " << trial;
    EXPECT_EQ(BruteForceNonManifold(w.mesh), std::make_pair(0, 0)) << "trial " << trial;
    EXPECT_EQ(w.mesh.F.size(), t.F.size());
    EXPECT_GE(int(w.mesh.V.size()), int(t.V.size()) + vertices);  // at least one copy per split vertex
    for (size_t v = 0; v < w.mesh.V.size(); ++v) EXPECT_EQ(w.mesh.V[v], t.V[size_t(w.meshToLive[v])]);
    // renumbered and reordered: the same counts
    std::vector<int> perm(t.V.size());
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    TriData u;
    u.V.resize(t.V.size());
    for (size_t v = 0; v < t.V.size(); ++v) u.V[perm[v]] = t.V[v];
    for (const auto& f : t.F) u.F.push_back({perm[f[1]], perm[f[2]], perm[f[0]]});
    std::shuffle(u.F.begin(), u.F.end(), rng);
    WorkingCopy x = vcgext::PrepareWorkingCopy(u);
    EXPECT_EQ(x.nonManifoldEdges, edges);
    EXPECT_EQ(x.nonManifoldVertices, vertices);
  }
}

TEST(InputPrep, FarFromOriginWarnsAndAllDegenerateFails) {
  TriData s = testsupport::Icosphere(1);
  for (auto& p : s.V) p += Vec3(1e4, 0, 0);
  WorkingCopy w = vcgext::PrepareWorkingCopy(s);
  EXPECT_EQ(w.error, "");
  ASSERT_EQ(w.warnings.size(), 1u);
  EXPECT_NE(w.warnings[0].find("far from the origin"), std::string::npos);
  TriData near = testsupport::Icosphere(1);
  for (auto& p : near.V) p += Vec3(10, 0, 0);  // 5x its size: no warning
  EXPECT_TRUE(vcgext::PrepareWorkingCopy(near).warnings.empty());
  TriData flat;
  flat.V = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}};
  flat.F = {{0, 1, 2}};
  EXPECT_NE(vcgext::PrepareWorkingCopy(flat).error.find("degenerate"), std::string::npos);
}

// A unit sphere at x = 1e7 in floats (MeshLab 2020.09's layer, the corpus's far1e7.off): float's
// steps there (1.19) are a third of its diagonal, so the shape is gone: a clear error. The same
// sphere in doubles keeps its shape (a warning only), and at 1e4 floats (steps 1e-3, 0.03 % of the
// diagonal) only warn.
TEST(InputPrep, FloatsThatLostTheShapeAreAnError) {
  TriData s = testsupport::Icosphere(2);
  for (auto& p : s.V) p += Vec3(1e7, 0, 0);
  TriData rounded = s;
  ASSERT_FALSE(vcgext::RoundCoordinatesToFloat(rounded.V));  // (it spares far objects)
  for (auto& p : rounded.V)
    for (int k = 0; k < 3; ++k) p[k] = vcgext::RoundedToFloat(p[k]);
  const WorkingCopy lost = vcgext::PrepareWorkingCopy(rounded);
  EXPECT_NE(lost.error.find("shape is lost"), std::string::npos) << lost.error;
  EXPECT_TRUE(lost.mesh.F.empty());
  const WorkingCopy exact = vcgext::PrepareWorkingCopy(s);
  EXPECT_EQ(exact.error, "");
  ASSERT_EQ(exact.warnings.size(), 1u);
  EXPECT_NE(exact.warnings[0].find("far from the origin"), std::string::npos);
  TriData near = testsupport::Icosphere(2);
  for (auto& p : near.V) {
    p += Vec3(1e4, 0, 0);
    for (int k = 0; k < 3; ++k) p[k] = vcgext::RoundedToFloat(p[k]);
  }
  const WorkingCopy nearCopy = vcgext::PrepareWorkingCopy(near);
  EXPECT_EQ(nearCopy.error, "");
  EXPECT_EQ(nearCopy.warnings.size(), 1u);
}

TEST(InputPrep, CoincidentVerticesThatMustStayApartAreNotMerged) {
  // two tetrahedra touching at one point, each with its own copy of that point (a manifold
  // mesh as given, as cow.off and diplodocus.off of the data set): merging would make it
  // non-manifold, so the copies stay apart
  TriData t;
  t.V = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  t.F = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {4, 6, 5}, {4, 5, 7}, {4, 7, 6}, {5, 6, 7}};
  WorkingCopy w = vcgext::PrepareWorkingCopy(t);
  ASSERT_EQ(w.error, "");
  EXPECT_EQ(w.mergedVertices, 0);
  EXPECT_EQ(w.mesh.V.size(), 8u);
  ASSERT_FALSE(w.notes.empty());
  EXPECT_NE(w.notes[0].find("kept 1 coincident"), std::string::npos) << w.notes[0];
}

// Coordinates beyond kMaxCoordinate: a clear error where the layer is read, and in Fitmaps'
// array entry point, before any ray is cast (Debian's Embree aborts on rays beyond 1.844e18:
// the fuzzer's tests/fuzz/regressions/embree_ray_origin_beyond_1.8e18).
TEST(InputPrep, CoordinatesBeyondTheRayCastersRangeAreAClearError) {
  for (double scale : {1e16, 1e18, 1e30}) {
    TriData s = testsupport::Icosphere(1, scale);
    vcgext::TMesh m;
    testsupport::ToVcg(s, m);
    const WorkingCopy w = vcgext::PrepareWorkingCopy(m);
    if (scale <= vcgext::kMaxCoordinate) {
      EXPECT_EQ(w.error, "") << scale;
      continue;
    }
    EXPECT_NE(w.error.find("beyond 1e17"), std::string::npos) << scale << ": " << w.error;
    EXPECT_NE(w.error.find("scale the mesh down"), std::string::npos) << w.error;
  }
}

// A large layer's working copy is kept for the next filter of a pipeline (input_prep.h): the same
// arrays give the same copy, any change of them a fresh one (compared with a mesh prepared
// after another mesh pushed it out).
TEST(InputPrep, RepeatedLargeLayerGivesTheSameCopyAndAChangedOneAFreshCopy) {
  TriData big = testsupport::PlaneGrid(330, 330);  // 217 800 triangles: above the memo's 200k
  for (size_t i = 0; i < big.F.size(); i += 1000) std::swap(big.F[i][1], big.F[i][2]);  // to repair
  ASSERT_GE(big.F.size(), 200000u);
  const WorkingCopy a = vcgext::PrepareWorkingCopy(big);
  const WorkingCopy b = vcgext::PrepareWorkingCopy(big);
  ASSERT_EQ(a.error, "");
  EXPECT_GT(a.flippedFaces, 0);
  EXPECT_EQ(b.mesh.V, a.mesh.V);
  EXPECT_EQ(b.mesh.F, a.mesh.F);
  EXPECT_EQ(b.liveToMesh, a.liveToMesh);
  EXPECT_EQ(b.notes, a.notes);
  EXPECT_EQ(b.flippedFaces, a.flippedFaces);
  // one coordinate changed: not the kept copy
  TriData moved = big;
  moved.V[12345][2] += 0.25;
  const WorkingCopy c = vcgext::PrepareWorkingCopy(moved);
  ASSERT_EQ(c.error, "");
  ASSERT_EQ(c.mesh.V.size(), a.mesh.V.size());
  EXPECT_NE(c.mesh.V, a.mesh.V);
  // one face changed (re-oriented): not the kept copy either
  TriData flipped = big;
  std::swap(flipped.F[7][1], flipped.F[7][2]);
  const WorkingCopy d = vcgext::PrepareWorkingCopy(flipped);
  EXPECT_EQ(d.flippedFaces, a.flippedFaces + 1);
  // and the first mesh again, after the others: the same copy as the first time
  const WorkingCopy e = vcgext::PrepareWorkingCopy(big);
  EXPECT_EQ(e.mesh.F, a.mesh.F);
  EXPECT_EQ(e.flippedFaces, a.flippedFaces);
}

// CoordinatePrecision::Float (what the 2022.02+ plugin sets): every coordinate rounded to float,
// as MeshLab 2020.09 reads it. Checked against float's own rounding one value at a time: g++ 12.2
// at -O2 turned the plain loop into the identity for two coordinates of three (the reason
// RoundCoordinatesToFloat goes through a volatile). A small object far from the origin, where
// float's spacing is coarser than 1e-6 of its size, keeps double.
TEST(InputPrep, RoundingToFloatRoundsEveryCoordinateAndSparesFarObjects) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> V(1001);
  for (Vec3& v : V) v = Vec3(u(rng), u(rng), u(rng));
  const std::vector<Vec3> before = V;
  ASSERT_TRUE(vcgext::RoundCoordinatesToFloat(V));
  int unrounded = 0, moved = 0;
  for (size_t i = 0; i < V.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      volatile float f = static_cast<float>(before[i][k]);
      unrounded += V[i][k] != static_cast<double>(f);
      moved += V[i][k] != before[i][k];
    }
  EXPECT_EQ(unrounded, 0);
  EXPECT_GT(moved, 2900);  // random doubles are almost never floats
  // 1 m object at 1e6 m from the origin: float's spacing there is 0.06 m
  std::vector<Vec3> far = before;
  for (Vec3& v : far) v += Vec3(1e6, 0, 0);
  const std::vector<Vec3> farBefore = far;
  EXPECT_FALSE(vcgext::RoundCoordinatesToFloat(far));
  EXPECT_TRUE(far == farBefore);
}

namespace {
// A double-precision vcg mesh, like MeshLab 2022.02+'s CMeshO.
class DV;
class DF;
struct DU : public vcg::UsedTypes<vcg::Use<DV>::AsVertexType, vcg::Use<DF>::AsFaceType> {};
class DV : public vcg::Vertex<DU, vcg::vertex::Coord3d, vcg::vertex::BitFlags> {};
class DF : public vcg::Face<DU, vcg::face::VertexRef, vcg::face::BitFlags> {};
class DM : public vcg::tri::TriMesh<std::vector<DV>, std::vector<DF>> {};
}  // namespace

// The process-wide switch: AsGiven by default (the layer's doubles as they are); under Float
// PrepareWorkingCopy of a double layer computes on the float-rounded coordinates.
TEST(InputPrep, WorkingCopyOfADoubleLayerIsRoundedOnlyUnderFloatPrecision) {
  const TriData t = testsupport::Icosphere(2);
  DM m;
  vcg::tri::Allocator<DM>::AddVertices(m, t.V.size());
  vcg::tri::Allocator<DM>::AddFaces(m, t.F.size());
  for (size_t i = 0; i < t.V.size(); ++i) m.vert[i].P() = vcg::Point3d(t.V[i][0], t.V[i][1], t.V[i][2]) * (1.0 / 3.0);
  for (size_t f = 0; f < t.F.size(); ++f)
    for (int k = 0; k < 3; ++k) m.face[f].V(k) = &m.vert[t.F[f][k]];
  auto floats = [](const TriData& d) {  // coordinates that are floats
    int n = 0;
    for (const Vec3& v : d.V)
      for (int k = 0; k < 3; ++k) {
        volatile float f = static_cast<float>(v[k]);
        n += v[k] == static_cast<double>(f);
      }
    return n;
  };
  ASSERT_EQ(vcgext::InputCoordinatePrecision(), vcgext::CoordinatePrecision::AsGiven);
  const WorkingCopy a = vcgext::PrepareWorkingCopy(m);
  vcgext::SetInputCoordinatePrecision(vcgext::CoordinatePrecision::Float);
  const WorkingCopy b = vcgext::PrepareWorkingCopy(m);
  vcgext::SetInputCoordinatePrecision(vcgext::CoordinatePrecision::AsGiven);
  ASSERT_TRUE(a.error.empty() && b.error.empty());
  ASSERT_EQ(a.mesh.V.size(), b.mesh.V.size());
  EXPECT_LT(floats(a.mesh), int(3 * a.mesh.V.size()) / 2);  // thirds are rarely floats
  EXPECT_EQ(floats(b.mesh), int(3 * b.mesh.V.size()));
}
