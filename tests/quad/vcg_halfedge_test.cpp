// vcglib's half-edge quad operators (vcg/complex/algorithms/update/halfedge_topology.h, MeshLab
// 2020.09) compared with QuadMesh's on small hand-made configurations of a 4x4 quad grid. The
// grid is converted with UpdateTopology::FaceFace + UpdateHalfEdges::FromIndexed into a polygon
// mesh with half-edges (type below); faces are compared as cyclic vertex sequences up to
// rotation (vertex ids are the same in both meshes), plus live counts and surviving positions.
//
// Where vcglib's operators work (tested here, same connectivity as ours):
//  - diagonal_collapse_quad on a face with four interior corners: same faces, same survivor
//    (the vertex passed in = our corner k), both at the midpoint.
//  - doublet_remove_quad on an interior valence-2 vertex: same faces (the original cell back).
//  - edge_rotate_quad on an interior edge (also with a boundary endpoint, separate experiment):
//    cw = false is our SwapEdge variant 0, cw = true is variant 1.
//  - diagonal_collapse_quad with one boundary corner, if the boundary corner is passed as the
//    survivor: same faces, but vcg always puts the survivor at the midpoint, so the boundary
//    vertex leaves the boundary line (ours keeps the boundary corner's position). Passing the
//    interior corner instead keeps the interior id (same faces up to that renaming).
//  - diagonal_collapse_quad of the boundary-boundary diagonal of a corner face ("ear" case in
//    its code): same result as our RemoveBoundaryCorner (merge at the midpoint) except that the
//    removed corner vertex stays alive and isolated (VHp == NULL, not deleted, still in m.vn).
//
// Where they do not (observed in a separate program, /tmp/vcg_he_exp, Release build with
// NDEBUG, on the same grid; these calls are deliberately not made here):
//  - No refusals at all: every precondition is an assert (compiled out in Release). The operators
//    return pointers, never a failure code, and nothing checks the result.
//  - doublet_remove_quad on a boundary vertex with one face (grid corner): segfault (NULL face).
//    On an interior valence-4 vertex: returns, mesh corrupted (CheckConsistency fails).
//    QuadMesh::RemoveDoublet returns NotDoublet for both.
//  - edge_rotate_quad on a boundary edge: segfault (the opposite face is NULL). Ours: BoundaryEdge.
//  - diagonal_collapse_quad joining two boundary vertices across a 3x1 strip (a pinch): the
//    result has two faces sharing one vertex only (non-manifold vertex); even
//    check_diagonal_collapse_quad returns true for it. Ours: BoundaryMerge.
//  - diagonal_collapse_quad of a diagonal shared with another face (two faces A,B,C,v and
//    C,D,A,v): produces the degenerate face (A, x, A, v). check_diagonal_collapse_quad does
//    refuse it (rings share > 2 vertices); ours returns Degenerate and rolls back.
//
// What vcglib lacks (read in halfedge_topology.h, not assumed):
//  - Undo: operators edit pointers and positions in place (vp->P() = midpoint), Allocator::Delete*
//    only flags elements; there is no journal or inverse operator. QuadMesh rolls back every
//    refused step (Begin/Rollback/Commit), which the simplifier needs.
//  - Link-condition / validity checks inside the operators: only asserts (doublet-free face,
//    no singlet, four distinct vertices). check_diagonal_collapse_quad is a separate, public
//    function that the operator does not call; it (1) overwrites the first corner's fan with
//    the second's (`faces.assign` twice), so only one fan is checked for boundary gaps,
//    (2) builds 1-rings with getVertices, documented "must be a non-border vertex": on a
//    boundary corner it misses the neighbour across the border (ring(5) = {0, 1, 6, 11} on the
//    grid, 10 missing), so it returns false for every boundary collapse tried and would trip its
//    assert(size >= 2) in a debug build, (3) accepts iff the rings share exactly 2 vertices,
//    which is conservative: it refuses collapses that leave a doublet (tested below), which
//    QuadMesh allows because the simplifier removes doublets at once.
//  - Boundary handling: the survivor is always moved to the midpoint; boundary-boundary merges
//    are not refused (only the ear case is handled); no boundary doublet operator.
//  - A mesh type: all of this needs a polygon mesh with half-edges (HEdge with HVAdj, HNextAdj,
//    HPrevAdj, HOppAdj, HFAdj; VHAdj; PolyInfo/PFVAdj/PFFAdj/PFHAdj faces) built from the
//    indexed mesh, while the rest of the pipeline works on indexed quads.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <vcg/complex/complex.h>
#include <vcg/simplex/face/component_polygon.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/algorithms/update/halfedge_indexed.h>

#include "quad_test_util.h"
#include "test_support.h"
#include "vcg_ext/quad/quad_mesh.h"

namespace {

// ------------------------------------------------------------------ a vcg polygon mesh with half-edges
struct HVertex;
struct HEdgeE;
struct HFace;
struct HHEdge;
struct HUsedTypes : public vcg::UsedTypes<vcg::Use<HVertex>::AsVertexType, vcg::Use<HEdgeE>::AsEdgeType,
                                          vcg::Use<HFace>::AsFaceType, vcg::Use<HHEdge>::AsHEdgeType> {};
struct HVertex : public vcg::Vertex<HUsedTypes, vcg::vertex::Coord3d, vcg::vertex::BitFlags, vcg::vertex::VHAdj> {};
struct HEdgeE : public vcg::Edge<HUsedTypes, vcg::edge::VertexRef, vcg::edge::BitFlags> {};
struct HFace : public vcg::Face<HUsedTypes, vcg::face::PolyInfo, vcg::face::PFVAdj, vcg::face::PFFAdj,
                                vcg::face::PFHAdj, vcg::face::BitFlags> {};
struct HHEdge : public vcg::HEdge<HUsedTypes, vcg::hedge::BitFlags, vcg::hedge::HVAdj, vcg::hedge::HNextAdj,
                                  vcg::hedge::HPrevAdj, vcg::hedge::HOppAdj, vcg::hedge::HFAdj> {};
struct HMesh : public vcg::tri::TriMesh<std::vector<HVertex>, std::vector<HEdgeE>, std::vector<HFace>,
                                        std::vector<HHEdge>> {};
using Topo = vcg::tri::HalfEdgeTopology<HMesh>;

// Indexed quads -> vcg polygon mesh (same vertex order) -> half-edges.
void BuildHalfEdgeMesh(const vcgext::QuadData& q, HMesh& m) {
  vcg::tri::Allocator<HMesh>::AddVertices(m, q.V.size());
  for (size_t i = 0; i < q.V.size(); ++i) m.vert[i].P() = vcg::Point3d(q.V[i].x(), q.V[i].y(), q.V[i].z());
  vcg::tri::Allocator<HMesh>::AddFaces(m, q.F.size());
  for (size_t i = 0; i < q.F.size(); ++i) {
    m.face[i].Alloc(4);
    for (int j = 0; j < 4; ++j) m.face[i].V(j) = &m.vert[q.F[i][j]];
  }
  vcg::tri::UpdateTopology<HMesh>::FaceFace(m);
  vcg::tri::UpdateHalfEdges<HMesh>::FromIndexed(m);
}

int VertIndex(const HMesh& m, const HVertex* v) { return int(v - &m.vert[0]); }

using testsupport::CanonicalCycle;

// Live faces of the half-edge mesh as sorted canonical cycles (walking HNp from FHp).
std::vector<std::vector<int>> Faces(const HMesh& m) {
  std::vector<std::vector<int>> out;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    std::vector<int> c;
    HHEdge* h = f.cFHp();
    do {
      c.push_back(VertIndex(m, h->HVp()));
      h = h->HNp();
    } while (h != f.cFHp() && c.size() <= 8);
    out.push_back(CanonicalCycle(c));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::vector<int>> Faces(const vcgext::quad::QuadMesh& q) {
  std::vector<std::vector<int>> out;
  for (int f = 0; f < q.NumFaceSlots(); ++f)
    if (q.FaceAlive(f)) out.push_back(CanonicalCycle({q.F[f][0], q.F[f][1], q.F[f][2], q.F[f][3]}));
  std::sort(out.begin(), out.end());
  return out;
}

int LiveVerts(const HMesh& m) {
  int n = 0;
  for (const auto& v : m.vert) n += !v.IsD();
  return n;
}

// Structural validity of the half-edge mesh: vcglib's own CheckConsistency (next/prev/opposite
// mutual, face loops) plus what it does not look at: twins run in opposite directions, every
// live vertex with faces points (VHp) to a live half-edge leaving it.
std::string HalfEdgeProblem(HMesh& m) {
  if (!vcg::tri::UpdateHalfEdges<HMesh>::CheckConsistency(m)) return "UpdateHalfEdges::CheckConsistency failed";
  for (auto& h : m.hedge) {
    if (h.IsD()) continue;
    if (h.HVp()->IsD()) return "half-edge from a deleted vertex";
    if (h.HOp()->HVp() != h.HNp()->HVp()) return "twin does not start where the half-edge ends";
  }
  for (auto& v : m.vert) {
    if (v.IsD()) continue;
    if (!v.VHp()) return "live vertex without half-edge";
    if (v.VHp()->IsD() || v.VHp()->HVp() != &v) return "VHp does not leave its vertex";
  }
  return "";
}

constexpr int kN = 4;  // 4x4 grid of quads, vertex (i, j) = j * 5 + i; interior vertices i, j in 1..3
int Id(int i, int j) { return j * (kN + 1) + i; }
int Cell(int i, int j) { return j * kN + i; }  // face index of grid cell (i, j)

}  // namespace

TEST(VcgHalfEdge, ConversionPreservesTheQuads) {
  auto q = quadtest::QuadGrid(kN, kN);
  HMesh m;
  BuildHalfEdgeMesh(q, m);
  EXPECT_EQ(HalfEdgeProblem(m), "");
  vcgext::quad::QuadMesh qm(q.V, q.F);
  ASSERT_EQ(qm.Check(), "");
  EXPECT_EQ(Faces(m), Faces(qm));
  // 16 faces * 4 half-edges + 16 boundary half-edges (a border loop)
  EXPECT_EQ(m.hn, 16 * 4 + 16);
}

TEST(VcgHalfEdge, DiagonalCollapseMatchesQuadMesh) {
  auto q = quadtest::QuadGrid(kN, kN);
  const int f = Cell(1, 1);  // corners (1,1) (2,1) (2,2) (1,2): all interior
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k);
    vcgext::quad::QuadMesh qm(q.V, q.F);
    const int a = qm.F[f][k], c = qm.F[f][k + 2];
    const vcgext::Vec3 mid = 0.5 * (q.V[a] + q.V[c]);
    int survivor = -1;
    ASSERT_EQ(qm.CollapseDiagonal(f, k, &survivor), vcgext::quad::OpResult::Ok);
    EXPECT_EQ(qm.Check(), "");
    EXPECT_EQ(survivor, a);
    EXPECT_FALSE(qm.VertAlive(c));

    HMesh m;
    BuildHalfEdgeMesh(q, m);
    // vcglib's pre-check (public) accepts this collapse
    HHEdge* hp = m.face[f].FHp();
    while (hp->HVp() != &m.vert[a]) hp = hp->HNp();
    EXPECT_TRUE(Topo::check_diagonal_collapse_quad(hp));
    HVertex* kept = Topo::diagonal_collapse_quad(m, &m.face[f], &m.vert[a]);
    ASSERT_EQ(HalfEdgeProblem(m), "");
    EXPECT_EQ(VertIndex(m, kept), a);
    EXPECT_TRUE(m.vert[c].IsD());
    EXPECT_TRUE(m.face[f].IsD());

    EXPECT_EQ(Faces(m), Faces(qm));
    EXPECT_EQ(m.fn, qm.NumFaces());
    EXPECT_EQ(m.fn, 15);
    EXPECT_EQ(LiveVerts(m), qm.NumVertices());
    EXPECT_EQ(m.vn, qm.NumVertices());
    // both place the survivor at the midpoint
    const auto& p = m.vert[a].cP();
    EXPECT_NEAR((vcgext::Vec3(p[0], p[1], p[2]) - mid).norm(), 0.0, 1e-12);
    EXPECT_NEAR((qm.P[a] - mid).norm(), 0.0, 1e-12);
  }
}

TEST(VcgHalfEdge, DoubletRemovalMatchesQuadMesh) {
  // Grid cell (1,1) = (A, B, C, D) split through a new centre vertex v along its diagonal A-C:
  // (A, B, C, v) and (C, D, A, v). v is an interior valence-2 vertex (doublet).
  auto q = quadtest::QuadGrid(kN, kN);
  const int f = Cell(1, 1);
  const vcgext::Quad cell = q.F[f];
  const int v = int(q.V.size());
  q.V.push_back(0.25 * (q.V[cell[0]] + q.V[cell[1]] + q.V[cell[2]] + q.V[cell[3]]));
  q.F[f] = {cell[0], cell[1], cell[2], v};
  q.F.push_back({cell[2], cell[3], cell[0], v});

  vcgext::quad::QuadMesh qm(q.V, q.F);
  EXPECT_NE(qm.Check(), "");  // the doublet itself is invalid for QuadMesh
  ASSERT_EQ(qm.RemoveDoublet(v), vcgext::quad::OpResult::Ok);
  EXPECT_EQ(qm.Check(), "");
  EXPECT_EQ(qm.NumFaces(), 16);

  HMesh m;
  BuildHalfEdgeMesh(q, m);
  ASSERT_EQ(HalfEdgeProblem(m), "");
  ASSERT_EQ(Topo::vertex_valence(&m.vert[v]), 2);
  ASSERT_FALSE(Topo::isBorderVertex(&m.vert[v]));
  HFace* merged = Topo::doublet_remove_quad(m, &m.vert[v]);
  ASSERT_EQ(HalfEdgeProblem(m), "");
  EXPECT_TRUE(m.vert[v].IsD());
  EXPECT_FALSE(merged->IsD());
  EXPECT_EQ(Faces(m), Faces(qm));
  EXPECT_EQ(m.fn, qm.NumFaces());
  EXPECT_EQ(m.vn, qm.NumVertices());
  // both give back the original cell (up to rotation)
  std::vector<int> orig = CanonicalCycle({cell[0], cell[1], cell[2], cell[3]});
  auto fs = Faces(m);
  EXPECT_NE(std::find(fs.begin(), fs.end(), orig), fs.end());
}

TEST(VcgHalfEdge, EdgeRotationMatchesQuadMesh) {
  // Interior edge (2,1)-(2,2) between cells (1,1) and (2,1); both endpoints interior.
  auto q = quadtest::QuadGrid(kN, kN);
  const int f = Cell(1, 1);
  const int u = Id(2, 1), w = Id(2, 2);
  vcgext::quad::QuadMesh probe(q.V, q.F);
  const int k = probe.CornerOf(f, u);
  ASSERT_EQ(probe.F[f][(k + 1) & 3], w);  // half-edge k of f is u -> w
  ASSERT_EQ(probe.AcrossEdge(f, k), Cell(2, 1));

  std::vector<std::vector<int>> ours[2], theirs[2];
  for (int variant = 0; variant < 2; ++variant) {
    vcgext::quad::QuadMesh qm(q.V, q.F);
    ASSERT_EQ(qm.SwapEdge(f, k, variant), vcgext::quad::OpResult::Ok);
    EXPECT_EQ(qm.Check(), "");
    ours[variant] = Faces(qm);
  }
  for (int cw = 0; cw < 2; ++cw) {
    HMesh m;
    BuildHalfEdgeMesh(q, m);
    HHEdge* hp = m.face[f].FHp();
    while (hp->HVp() != &m.vert[u]) hp = hp->HNp();
    ASSERT_EQ(hp->HNp()->HVp(), &m.vert[w]);
    Topo::edge_rotate_quad(hp, cw != 0);
    ASSERT_EQ(HalfEdgeProblem(m), "");
    EXPECT_EQ(m.fn, 16);
    EXPECT_EQ(m.vn, int(q.V.size()));
    theirs[cw] = Faces(m);
  }
  EXPECT_NE(ours[0], ours[1]);
  // counter-clockwise (cw = false) is our variant 0 (new edge a-c), clockwise is variant 1 (b-d)
  EXPECT_EQ(theirs[0], ours[0]);
  EXPECT_EQ(theirs[1], ours[1]);
}

TEST(VcgHalfEdge, BoundaryCollapseSameConnectivityOtherPositions) {
  auto q = quadtest::QuadGrid(kN, kN);
  // (a) cell (0,1) = (5, 6, 11, 10), diagonal 5 (boundary) - 11 (interior), vcg keeping 5 like we do:
  // same faces, but vcg moves the boundary vertex to the midpoint (off the boundary line x = 0).
  {
    const int f = Cell(0, 1), b = Id(0, 1), c = Id(1, 2);
    vcgext::quad::QuadMesh qm(q.V, q.F);
    int survivor = -1;
    ASSERT_EQ(qm.CollapseDiagonal(f, 0, &survivor), vcgext::quad::OpResult::Ok);
    EXPECT_EQ(qm.Check(), "");
    EXPECT_EQ(survivor, b);
    EXPECT_EQ(qm.P[b], q.V[b]);  // ours: the boundary corner keeps its position
    HMesh m;
    BuildHalfEdgeMesh(q, m);
    Topo::diagonal_collapse_quad(m, &m.face[f], &m.vert[b]);
    ASSERT_EQ(HalfEdgeProblem(m), "");
    EXPECT_EQ(Faces(m), Faces(qm));
    EXPECT_DOUBLE_EQ(m.vert[b].P()[0], 0.5 * (q.V[b].x() + q.V[c].x()));  // = 0.125, no longer 0
  }
  // (b) corner cell (0,0) = (0, 1, 6, 5), diagonal 1-5 (both boundary): QuadMesh refuses the
  // collapse; vcg treats the corner face as an "ear", merges 1 and 5 at their midpoint: the same
  // as our RemoveBoundaryCorner(0) (survivor named 5 there, 1 in vcg), except that vcg leaves
  // vertex 0 alive with no half-edge (VHp == NULL) instead of deleting it.
  {
    vcgext::quad::QuadMesh qm(q.V, q.F);
    EXPECT_EQ(qm.CollapseDiagonal(Cell(0, 0), 1), vcgext::quad::OpResult::BoundaryMerge);
    int survivor = -1;
    ASSERT_EQ(qm.RemoveBoundaryCorner(0, &survivor, 0), vcgext::quad::OpResult::Ok);
    ASSERT_EQ(survivor, 5);
    EXPECT_EQ(qm.Check(), "");
    HMesh m;
    BuildHalfEdgeMesh(q, m);
    HVertex* kept = Topo::diagonal_collapse_quad(m, &m.face[Cell(0, 0)], &m.vert[1]);
    EXPECT_EQ(VertIndex(m, kept), 1);
    EXPECT_EQ(HalfEdgeProblem(m), "live vertex without half-edge");
    EXPECT_FALSE(m.vert[0].IsD());
    EXPECT_EQ(m.vert[0].VHp(), nullptr);
    auto ours = qm.F;  // rename our survivor 5 to vcg's 1
    for (auto& f : ours)
      for (auto& x : f)
        if (x == 5) x = 1;
    std::vector<std::vector<int>> expect;
    for (int f = 0; f < qm.NumFaceSlots(); ++f)
      if (qm.FaceAlive(f)) expect.push_back(CanonicalCycle({ours[f][0], ours[f][1], ours[f][2], ours[f][3]}));
    std::sort(expect.begin(), expect.end());
    EXPECT_EQ(Faces(m), expect);
    EXPECT_EQ(m.vert[1].cP()[0], qm.P[5].x());
    EXPECT_EQ(m.vert[1].cP()[1], qm.P[5].y());
  }
}

TEST(VcgHalfEdge, CollapseCheckIsSeparateAndConservative) {
  // check_diagonal_collapse_quad is not called by diagonal_collapse_quad; it accepts a collapse
  // iff the 1-rings of the two corners share exactly 2 vertices.
  auto q = quadtest::QuadGrid(kN, kN);
  const int a = Id(1, 1);
  vcgext::quad::QuadMesh qm(q.V, q.F);
  ASSERT_EQ(qm.CollapseDiagonal(Cell(1, 1), 0), vcgext::quad::OpResult::Ok);
  HMesh m;
  BuildHalfEdgeMesh(q, m);
  Topo::diagonal_collapse_quad(m, &m.face[Cell(1, 1)], &m.vert[a]);
  ASSERT_EQ(Faces(m), Faces(qm));
  // Second collapse of cell (1,2), now (11, 6, 17, 16), along 6-16: it leaves vertex 11 with two
  // faces (a doublet, which the simplifier removes next). QuadMesh allows it, vcg's check refuses
  // it (rings of 6 and 16 share 10, 11, 17).
  const int f = Cell(1, 2);
  ASSERT_EQ(qm.F[f][1], a);
  HHEdge* hp = m.face[f].FHp();
  while (hp->HVp() != &m.vert[a]) hp = hp->HNp();
  EXPECT_FALSE(Topo::check_diagonal_collapse_quad(hp));
  ASSERT_EQ(qm.CollapseDiagonal(f, 1), vcgext::quad::OpResult::Ok);
  EXPECT_EQ(qm.Valence(Id(1, 2)), 2);
  // the other diagonal of that face (11-17) is accepted by both
  hp = hp->HNp()->HNp()->HNp();  // leaves 11
  ASSERT_EQ(hp->HVp(), &m.vert[Id(1, 2)]);
  EXPECT_TRUE(Topo::check_diagonal_collapse_quad(hp));
}
