/// Tests of vcg_ext/quad/close_holes.h: which holes are closed, and that closing them adds faces
/// only (the vertices and the input's faces kept, so per-vertex data still hold), leaves a closed,
/// manifold, consistently oriented surface and about the area the holes lacked.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "test_support.h"
#include "vcg_ext/quad/close_holes.h"
#include "vcg_ext/quad/quad_simplify.h"

namespace {
// Every directed edge at most once (consistent orientation) and every edge in two faces at most.
void ExpectOrientedManifold(const vcgext::TriData& m) {
  std::set<std::pair<int, int>> directed;
  for (const auto& f : m.F)
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(directed.insert({f[c], f[(c + 1) % 3]}).second) << "edge used twice";
  int nme = 0, nmv = 0;
  vcgext::CountNonManifold(m, &nme, &nmv);
  EXPECT_EQ(nme, 0);
  EXPECT_EQ(nmv, 0);
}

// A 20 x 20 grid of the unit square with the cells of `holes` removed (i, j: the cell's corner).
vcgext::TriData GridWithHoles(const std::set<std::pair<int, int>>& holes) {
  vcgext::TriData g = testsupport::PlaneGrid(20, 20);
  vcgext::TriData out;
  out.V = g.V;
  for (size_t f = 0; f < g.F.size(); ++f) {
    const int cell = int(f / 2), i = cell % 20, j = cell / 20;  // PlaneGrid: two triangles per cell, rows of x
    if (!holes.count({i, j})) out.F.push_back(g.F[f]);
  }
  return out;
}
}  // namespace

// 30 one-ring holes of an icosphere (about 0.15 across, 4 % of the diagonal: above the 2 %, but of
// 5 or 6 edges): every one closed, the sphere closed again, no vertex added or moved, the input's
// faces first and unchanged, and the closing triangles' area about the removed one-rings' (the
// fans without their centre vertex, lower by its height over the rim's plane: within 5 %).
TEST(CloseHoles, SphereHolesClosedWithFacesOnly) {
  const vcgext::TriData full = testsupport::Icosphere(4), holed = testsupport::SphereWithHoles(30);
  const vcgext::CloseHolesResult r = vcgext::CloseSmallHoles(holed);
  EXPECT_TRUE(r.refused.empty()) << r.refused;
  EXPECT_EQ(r.holes, 30);
  EXPECT_EQ(r.closed, 30);
  EXPECT_EQ(r.skipped, 0);
  EXPECT_EQ(r.mesh.V, holed.V);
  ASSERT_GT(r.mesh.F.size(), holed.F.size());
  EXPECT_TRUE(std::equal(holed.F.begin(), holed.F.end(), r.mesh.F.begin()));
  EXPECT_TRUE(vcgext::BoundaryHalfEdges(r.mesh).empty());
  ExpectOrientedManifold(r.mesh);
  const double removed = vcgext::TotalArea(full) - vcgext::TotalArea(holed);
  const double added = vcgext::TotalArea(r.mesh) - vcgext::TotalArea(holed);
  EXPECT_NEAR(added, removed, 0.05 * removed);
  EXPECT_NEAR(r.closedAreaPct, 100 * added / vcgext::TotalArea(holed), 1e-9);
}

// On a grid: the outline is never a hole; a one-cell hole (4 edges, 5 % of the diagonal) is closed
// by default, a 6 x 6 cell one (30 % of the diagonal, 24 edges) only under a larger share, a hole
// of few edges above 10 % of the diagonal not at all; 0 closes nothing.
TEST(CloseHoles, SizeRuleAndOutline) {
  const vcgext::TriData plain = testsupport::PlaneGrid(20, 20);
  vcgext::CloseHolesParams all;
  all.maxDiagonalPercent = 100;
  const vcgext::CloseHolesResult none = vcgext::CloseSmallHoles(plain, all);
  EXPECT_EQ(none.holes, 0);
  EXPECT_EQ(none.closed, 0);
  EXPECT_EQ(none.mesh.F, plain.F);

  std::set<std::pair<int, int>> cells = {{2, 2}};
  for (int i = 8; i < 14; ++i)
    for (int j = 8; j < 14; ++j) cells.insert({i, j});
  const vcgext::TriData holed = GridWithHoles(cells);
  ASSERT_EQ(holed.F.size(), plain.F.size() - 2 * cells.size());
  const vcgext::CloseHolesResult small = vcgext::CloseSmallHoles(holed);
  EXPECT_EQ(small.holes, 2);
  EXPECT_EQ(small.closed, 1);
  EXPECT_EQ(small.mesh.F.size(), holed.F.size() + 2);  // a 4-edge loop: two triangles
  EXPECT_EQ(vcgext::BoundaryHalfEdges(small.mesh).size(), 80u + 24u);  // the outline and the large hole
  ExpectOrientedManifold(small.mesh);

  vcgext::CloseHolesParams wide;
  wide.maxDiagonalPercent = 40;
  const vcgext::CloseHolesResult both = vcgext::CloseSmallHoles(holed, wide);
  EXPECT_EQ(both.closed, 2);
  EXPECT_EQ(vcgext::BoundaryHalfEdges(both.mesh).size(), 80u);
  EXPECT_NEAR(vcgext::TotalArea(both.mesh), 1.0, 1e-9);  // flat: the grid's own area
  ExpectOrientedManifold(both.mesh);

  // few edges but large: the data set's triangular_hole.off (a 3-edge hole across 45 % of its
  // diagonal) keeps its hole, as does a one-cell hole of a 4 x 4 grid (25 %)
  const vcgext::CloseHolesResult feature = vcgext::CloseSmallHoles(testsupport::LoadSample("triangular_hole.off"));
  EXPECT_EQ(feature.holes, 1);
  EXPECT_EQ(feature.closed, 0);
  vcgext::TriData coarse = testsupport::PlaneGrid(4, 4);
  coarse.F.erase(coarse.F.begin() + 10, coarse.F.begin() + 12);  // cell (1, 1)
  const vcgext::CloseHolesResult cell = vcgext::CloseSmallHoles(coarse);
  EXPECT_EQ(cell.holes, 1);
  EXPECT_EQ(cell.closed, 0);

  vcgext::CloseHolesParams off;
  off.maxDiagonalPercent = 0;
  const vcgext::CloseHolesResult kept = vcgext::CloseSmallHoles(holed, off);
  EXPECT_EQ(kept.closed, 0);
  EXPECT_EQ(kept.mesh.F, holed.F);
}

// Two one-cell holes touching at a corner: the working copy splits that vertex into two copies (a
// manifold mesh), which makes the two holes one loop through both copies. They are joined again
// and the loop closed: one vertex fewer, the grid closed but for its outline, manifold, and the
// layer's vertex maps follow (every layer vertex still maps to a vertex at its position).
TEST(CloseHoles, HolesTouchingAtAVertexAreClosedWithTheVertexJoined) {
  vcgext::TMesh layer;
  testsupport::ToVcg(GridWithHoles({{5, 5}, {6, 6}}), layer);
  vcgext::WorkingCopy w = vcgext::PrepareWorkingCopy(layer);
  ASSERT_TRUE(w.error.empty()) << w.error;
  ASSERT_EQ(w.splitVertices, 1);
  const size_t before = w.mesh.V.size();
  vcgext::CloseHolesParams p;
  p.maxDiagonalPercent = 20;  // the two cells' box: 10 % of the grid's diagonal, 8 edges
  const vcgext::CloseHolesResult r = vcgext::CloseSmallHoles(w, p);
  EXPECT_TRUE(r.refused.empty()) << r.refused;
  EXPECT_GE(r.closed, 1);
  EXPECT_EQ(r.skipped, 0);
  EXPECT_EQ(r.joinedVertices, 1);
  EXPECT_EQ(w.mesh.V.size(), before - 1);
  EXPECT_EQ(vcgext::BoundaryHalfEdges(w.mesh).size(), 80u);
  ExpectOrientedManifold(w.mesh);
  EXPECT_NEAR(vcgext::TotalArea(w.mesh), 1.0, 1e-9);
  ASSERT_EQ(w.meshToLive.size(), w.mesh.V.size());
  for (size_t v = 0; v < w.mesh.V.size(); ++v) {
    const auto& p = layer.vert[size_t(w.meshToLive[v])].cP();
    EXPECT_NEAR((w.mesh.V[v] - vcgext::Vec3(p[0], p[1], p[2])).norm(), 0, 1e-6);
  }
  for (size_t i = 0; i < w.liveToMesh.size(); ++i) {
    ASSERT_GE(w.liveToMesh[i], 0);
    const auto& p = layer.vert[i].cP();
    EXPECT_NEAR((w.mesh.V[size_t(w.liveToMesh[i])] - vcgext::Vec3(p[0], p[1], p[2])).norm(), 0, 1e-6);
  }
}

// A hole round an island (a piece cut out by cracks: the removed cells as a separate piece with
// vertices of their own, 1e-6 above): closing it would double the island's sheet, so it stays
// open and is counted; the same hole without the island is closed.
TEST(CloseHoles, HoleRoundAnIslandStaysOpen) {
  const std::set<std::pair<int, int>> cells = {{5, 5}, {5, 6}, {6, 5}, {6, 6}};  // 10 % of the diagonal
  vcgext::TriData holed = GridWithHoles(cells);
  vcgext::CloseHolesParams p;
  p.maxDiagonalPercent = 15;
  const vcgext::CloseHolesResult open = vcgext::CloseSmallHoles(holed, p);
  EXPECT_EQ(open.holes, 1);
  EXPECT_EQ(open.closed, 1);
  EXPECT_EQ(open.islands, 0);

  const vcgext::TriData grid = testsupport::PlaneGrid(20, 20);
  vcgext::TriData withIsland = holed;
  for (size_t f = 0; f < grid.F.size(); ++f) {
    const int cell = int(f / 2);
    if (!cells.count({cell % 20, cell / 20})) continue;
    vcgext::Tri t;
    for (int c = 0; c < 3; ++c) {
      t[c] = int(withIsland.V.size());
      withIsland.V.push_back(grid.V[size_t(grid.F[f][c])] + vcgext::Vec3(0, 0, 1e-6));
    }
    withIsland.F.push_back(t);
  }
  const vcgext::CloseHolesResult island = vcgext::CloseSmallHoles(withIsland, p);
  EXPECT_EQ(island.holes, 1);  // the island's own loop is its outline
  EXPECT_EQ(island.closed, 0);
  EXPECT_EQ(island.islands, 1);
  EXPECT_EQ(island.mesh.F, withIsland.F);
}

// A hole whose rim runs straight through several vertices (a mesh refined by edge midpoints:
// bunny00 with 2 % of its faces deleted, ×16, had 101 such holes): ear cutting takes an ear of
// three collinear points when nothing else is left. Here an L of three cells on a grid with
// integer coordinates (exact collinearity; 8 rim vertices, two straight runs of three): the hole
// is closed (it was left open), by triangles that all have an area, the grid flat and whole again.
TEST(CloseHoles, CollinearRimIsClosedWithoutTrianglesOfNoArea) {
  const vcgext::TriData g = testsupport::PlaneGrid(20, 20, 20.0);
  vcgext::TriData holed;
  holed.V = g.V;
  const std::set<std::pair<int, int>> cells = {{4, 4}, {5, 4}, {5, 5}};
  for (size_t f = 0; f < g.F.size(); ++f) {
    const int cell = int(f / 2);
    if (!cells.count({cell % 20, cell / 20})) holed.F.push_back(g.F[f]);
  }
  vcgext::CloseHolesParams p;
  p.maxDiagonalPercent = 15;  // the hole's box: 10 % of the grid's diagonal
  const vcgext::CloseHolesResult r = vcgext::CloseSmallHoles(holed, p);
  EXPECT_TRUE(r.refused.empty()) << r.refused;
  EXPECT_EQ(r.holes, 1);
  EXPECT_EQ(r.skipped, 0);
  ASSERT_EQ(r.closed, 1);
  ASSERT_EQ(r.mesh.F.size(), holed.F.size() + 6);  // an 8-gon: six triangles
  for (size_t f = holed.F.size(); f < r.mesh.F.size(); ++f) {
    const auto& t = r.mesh.F[f];
    const vcgext::Vec3 n = (r.mesh.V[size_t(t[1])] - r.mesh.V[size_t(t[0])]).cross(r.mesh.V[size_t(t[2])] - r.mesh.V[size_t(t[0])]);
    EXPECT_GT(n.z(), 0) << "closing triangle " << f - holed.F.size() << " has no area or is flipped";
  }
  EXPECT_EQ(vcgext::BoundaryHalfEdges(r.mesh).size(), 80u);  // the outline only
  EXPECT_NEAR(vcgext::TotalArea(r.mesh), 400.0, 1e-9);
  ExpectOrientedManifold(r.mesh);
}

// The few-edges rule counts a hole's straight sides: a 2 x 2 cell hole of a 40 x 40 grid (5 % of
// the diagonal, 8 edges on 4 sides, what a one-cell hole of a 20 x 20 grid becomes when every edge
// is split at its midpoint) is closed as the one-cell hole is; a round hole of 8 edges as large
// is not (it has 8 sides).
TEST(CloseHoles, FewSidesRuleHoldsOnARefinedCopy) {
  vcgext::TriData g = testsupport::PlaneGrid(40, 40);
  vcgext::TriData square;
  square.V = g.V;
  for (size_t f = 0; f < g.F.size(); ++f) {
    const int cell = int(f / 2), i = cell % 40, j = cell / 40;
    if (!(i >= 10 && i < 12 && j >= 10 && j < 12)) square.F.push_back(g.F[f]);
  }
  const vcgext::CloseHolesResult r = vcgext::CloseSmallHoles(square);
  EXPECT_EQ(r.holes, 1);
  EXPECT_EQ(r.closed, 1);
  ExpectOrientedManifold(r.mesh);
  EXPECT_NEAR(vcgext::TotalArea(r.mesh), 1.0, 1e-9);

  // the same hole with its four side midpoints pushed out by a tenth of a cell: 8 sides
  vcgext::TriData round = square;
  const double c = 0.025;  // one cell
  round.V[size_t(10 * 41 + 11)].y() -= 0.1 * c;  // (11, 10): bottom side's middle
  round.V[size_t(12 * 41 + 11)].y() += 0.1 * c;  // (11, 12): top
  round.V[size_t(11 * 41 + 10)].x() -= 0.1 * c;  // (10, 11): left
  round.V[size_t(11 * 41 + 12)].x() += 0.1 * c;  // (12, 11): right
  const vcgext::CloseHolesResult o = vcgext::CloseSmallHoles(round);
  EXPECT_EQ(o.holes, 1);
  EXPECT_EQ(o.closed, 0);
}

// A hole that stays open (here round an island) through two copies of one point: those copies are
// not joined (joined, they pinch its rim into a non-manifold vertex, which refused every closing),
// and the other holes are closed as without it.
TEST(CloseHoles, CopiesOfAnOpenLoopStayApartAndTheOthersClose) {
  const std::set<std::pair<int, int>> cells = {{5, 5}, {6, 6}, {2, 2}};
  const vcgext::TriData holed = GridWithHoles(cells);
  vcgext::TMesh layer;
  testsupport::ToVcg(holed, layer);
  vcgext::WorkingCopy w = vcgext::PrepareWorkingCopy(layer);
  ASSERT_TRUE(w.error.empty()) << w.error;
  ASSERT_EQ(w.splitVertices, 1);
  // an island over the two touching cells, 1e-6 above: their loop doubles a sheet
  const vcgext::TriData grid = testsupport::PlaneGrid(20, 20);
  for (size_t f = 0; f < grid.F.size(); ++f) {
    const int cell = int(f / 2);
    const std::pair<int, int> ij{cell % 20, cell / 20};
    if (ij != std::make_pair(5, 5) && ij != std::make_pair(6, 6)) continue;
    vcgext::Tri t;
    for (int c = 0; c < 3; ++c) {
      t[c] = int(w.mesh.V.size());
      w.mesh.V.push_back(grid.V[size_t(grid.F[f][c])] + vcgext::Vec3(0, 0, 1e-6));
    }
    w.mesh.F.push_back(t);
  }
  vcgext::CloseHolesParams p;
  p.maxDiagonalPercent = 20;
  const vcgext::CloseHolesResult r = vcgext::CloseSmallHoles(w.mesh, p);
  EXPECT_TRUE(r.refused.empty()) << r.refused;
  EXPECT_EQ(r.islands, 1);
  EXPECT_EQ(r.closed, 1);
  EXPECT_EQ(r.joinedVertices, 0);
  EXPECT_EQ(r.mesh.V, w.mesh.V);
  ExpectOrientedManifold(r.mesh);
  EXPECT_EQ(vcgext::BoundaryHalfEdges(r.mesh).size(), vcgext::BoundaryHalfEdges(w.mesh).size() - 4);
}
