// Quad layers in MeshLab's faux-edge convention <-> QuadData.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <type_traits>

#include <gtest/gtest.h>

#include "test_support.h"
#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/io/mesh_io.h"

namespace {

vcgext::QuadData Grid(int n) {
  vcgext::QuadData q;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) q.V.emplace_back(i, j, 0.1 * i * j);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      int a = j * (n + 1) + i;
      q.F.push_back({a, a + 1, a + n + 2, a + n + 1});
    }
  return q;
}

using testsupport::CanonicalFaceSet;

TEST(VcgBridge, QuadRoundTripKeepsFacesAndOrientation) {
  auto q = Grid(4);
  vcgext::TMesh m;
  vcgext::ExportQuads(q, m);
  EXPECT_EQ(m.fn, 2 * int(q.F.size()));
  vcgext::QuadData back;
  ASSERT_EQ(vcgext::ImportQuads(m, back), "");
  ASSERT_EQ(back.F.size(), q.F.size());
  EXPECT_EQ(CanonicalFaceSet(q.F), CanonicalFaceSet(back.F));
  for (size_t i = 0; i < q.V.size(); ++i) EXPECT_NEAR((q.V[i] - back.V[i]).norm(), 0.0, 1e-6);
}

TEST(VcgBridge, WedgeUVsFollowQuadCorners) {
  auto q = Grid(2);
  std::vector<std::array<Eigen::Vector2d, 4>> uv(q.F.size());
  for (size_t i = 0; i < q.F.size(); ++i)
    for (int k = 0; k < 4; ++k) uv[i][k] = Eigen::Vector2d(i + 0.1 * k, 0.5 * k);
  vcgext::TMesh m;
  vcgext::ExportQuads(q, m, &uv);
  // Every wedge's UV is the one of its quad corner (same vertex).
  for (size_t i = 0; i < q.F.size(); ++i)
    for (int h = 0; h < 2; ++h)
      for (int k = 0; k < 3; ++k) {
        const auto& f = m.face[2 * i + h];
        int vid = int(vcg::tri::Index(m, f.cV(k)));
        int corner = -1;
        for (int c = 0; c < 4; ++c)
          if (q.F[i][c] == vid) corner = c;
        ASSERT_GE(corner, 0);
        EXPECT_NEAR(f.cWT(k).U(), uv[i][corner][0], 1e-6);
        EXPECT_NEAR(f.cWT(k).V(), uv[i][corner][1], 1e-6);
      }
}

TEST(VcgBridge, RejectsNonQuadLayersWithCounts) {
  vcgext::TMesh m;
  vcgext::QuadData q;
  EXPECT_NE(vcgext::ImportQuads(m, q).find("empty"), std::string::npos);
  testsupport::ToVcg(testsupport::PlaneGrid(2, 2), m);  // 8 triangles, no faux edges
  std::string err = vcgext::ImportQuads(m, q);
  EXPECT_NE(err.find("8 triangles"), std::string::npos) << err;
  // Mark a faux edge on one triangle only: unmatched.
  testsupport::ToVcg(testsupport::PlaneGrid(1, 1), m);
  m.face[0].SetF(0);
  err = vcgext::ImportQuads(m, q);
  EXPECT_FALSE(err.empty());
  // A pentagon (a triangle with two faux edges) is rejected.
  vcgext::ExportQuads(Grid(1), m);
  m.face[0].SetF(0);
  err = vcgext::ImportQuads(m, q);
  EXPECT_NE(err.find("more than four"), std::string::npos) << err;
}

TEST(VcgBridge, QuadsSharingOppositeCornersRoundTrip) {
  // Two quads whose opposite corners are the same two vertices (0 and 2), as a simplified control
  // mesh can have: splitting both along 0-2 would make 0-2 a non-manifold triangle edge with
  // two identical directed faux edges, and the pairing on import ambiguous.
  vcgext::QuadData q;
  q.V = {vcgext::Vec3(0, 0, 0), vcgext::Vec3(1, -1, 0), vcgext::Vec3(2, 0, 0), vcgext::Vec3(1, 1, 0),
         vcgext::Vec3(1, -1, 1), vcgext::Vec3(1, 1, 1)};
  q.F = {{0, 1, 2, 3}, {0, 4, 2, 5}};
  vcgext::TMesh m;
  EXPECT_EQ(vcgext::ExportQuads(q, m), 0);
  vcgext::QuadData back;
  ASSERT_EQ(vcgext::ImportQuads(m, back), "");
  EXPECT_EQ(CanonicalFaceSet(q.F), CanonicalFaceSet(back.F));
  // The same layer split naively (both along 0-2, as MeshLab's PLY importer fans polygons) is
  // paired by normal agreement: the true halves are coplanar here, the wrong ones are not.
  for (int h = 0; h < 2; ++h) {
    auto& t = m.face[2 + h];
    const int c[2][3] = {{0, 4, 2}, {0, 2, 5}};
    for (int k = 0; k < 3; ++k) t.V(k) = &m.vert[c[h][k]];
    t.ClearAllF();
    t.SetF(h == 0 ? 2 : 0);
  }
  int resolved = -1;
  ASSERT_EQ(vcgext::ImportQuads(m, back, &resolved), "");
  EXPECT_EQ(resolved, 1);
  EXPECT_EQ(CanonicalFaceSet(q.F), CanonicalFaceSet(back.F));
}

// LayerRoundTrip (what the simplification's fitted measures predict the report from) is the
// layer's own round trip, ExportQuads then ImportQuads, bit for bit: float coordinates, the same
// faces in the same order with the same first corners. The second quad of the pair sharing
// opposite corners is split along its other diagonal, so it comes back starting at its corner b.
TEST(VcgBridge, LayerRoundTripIsExportThenImport) {
  vcgext::QuadData shared;
  shared.V = {vcgext::Vec3(0, 0, 0), vcgext::Vec3(1, -1, 0), vcgext::Vec3(2, 0, 0), vcgext::Vec3(1, 1, 0),
              vcgext::Vec3(1, -1, 1), vcgext::Vec3(1, 1, 1)};
  shared.F = {{0, 1, 2, 3}, {0, 4, 2, 5}};
  vcgext::QuadData grid = Grid(3);
  for (auto& v : grid.V) v += vcgext::Vec3(1.0 / 3, 1.0 / 7, 0.1);  // not floats
  for (const vcgext::QuadData& q : {shared, grid}) {
    vcgext::TMesh m;
    vcgext::ExportQuads(q, m);
    vcgext::QuadData back;
    ASSERT_EQ(vcgext::ImportQuads(m, back), "");
    const vcgext::QuadData trip = vcgext::LayerRoundTrip(q);
    EXPECT_EQ(trip.V, back.V);
    EXPECT_EQ(trip.F, back.F);
  }
  const vcgext::QuadData trip = vcgext::LayerRoundTrip(shared);
  ASSERT_EQ(trip.F.size(), 2u);
  EXPECT_EQ(trip.F[0], shared.F[0]);
  EXPECT_EQ(trip.F[1], (vcgext::Quad{4, 2, 5, 0}));
  // rounded to the layer's scalar (MESHLAB_SCALAR): float for MeshLab 2020.09 (TMesh's, above),
  // unchanged for the 2025 build's double layers
  if (std::is_same_v<MESHLAB_SCALAR, float>)
    EXPECT_NE(vcgext::LayerRoundTrip(grid).V, grid.V);
  else
    EXPECT_EQ(vcgext::LayerRoundTrip(grid).V, grid.V);
}

TEST(VcgBridge, ExportTrianglesWritesQuality) {
  auto d = testsupport::PlaneGrid(3, 3);
  std::vector<double> q(d.V.size());
  for (size_t i = 0; i < q.size(); ++i) q[i] = double(i) * 0.5;
  vcgext::TMesh m;
  vcgext::ExportTriangles(d, m, &q);
  ASSERT_EQ(m.vn, int(d.V.size()));
  ASSERT_EQ(m.fn, int(d.F.size()));
  for (size_t i = 0; i < q.size(); ++i) EXPECT_FLOAT_EQ(m.vert[i].Q(), float(q[i]));
}

}  // namespace

// A polygonal PLY (a pentagon, a quad, a triangle) through vcglib's own importer, which fans the
// polygons with faux edges as MeshLab's does: ImportPolygons gives the polygons back;
// ImportQuads refuses the layer.
TEST(VcgBridge, ImportPolygonsReadsWhatThePlyImporterFanned) {
  const std::string path = testsupport::ScratchDir() + "/polygons.ply";
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 1 0\n-1 1 0\n-1 0 0\n0 -1 0\n"
                         "5 0 1 2 3 4\n4 0 4 5 6\n3 0 6 7\n";
  vcgext::TMesh m;
  ASSERT_EQ(vcgext::LoadMesh(path, m), "");
  ASSERT_EQ(m.fn, 3 + 2 + 1);
  vcgext::PolyData p;
  ASSERT_EQ(vcgext::ImportPolygons(m, p), "");
  ASSERT_EQ(p.V.size(), 8u);
  const std::vector<std::vector<int>> expected = {{0, 1, 2, 3, 4}, {0, 4, 5, 6}, {0, 6, 7}};
  EXPECT_EQ(CanonicalFaceSet(p.F), CanonicalFaceSet(expected));
  vcgext::QuadData q;
  EXPECT_NE(vcgext::ImportQuads(m, q).find("not pure-quad"), std::string::npos);
  // A pure-quad layer reads as the same quads either way.
  vcgext::TMesh g;
  vcgext::ExportQuads(Grid(3), g);
  ASSERT_EQ(vcgext::ImportPolygons(g, p), "");
  std::vector<std::vector<int>> grid;
  for (const auto& f : Grid(3).F) grid.push_back({f[0], f[1], f[2], f[3]});
  EXPECT_EQ(CanonicalFaceSet(p.F), CanonicalFaceSet(grid));
}

// With `flipped`, quads stored reversed against their neighbours (an export, parts merged) read
// back as the grid they belong to; the layer itself is not modified. Without it they read as stored.
TEST(VcgBridge, ImportOrientsQuadsStoredReversedWhenAsked) {
  vcgext::QuadData g = Grid(4);
  for (int f : {1, 6, 11}) std::reverse(g.F[f].begin(), g.F[f].end());
  vcgext::TMesh m;
  vcgext::ExportQuads(g, m);
  vcgext::QuadData asStored, oriented;
  ASSERT_EQ(vcgext::ImportQuads(m, asStored), "");
  EXPECT_EQ(CanonicalFaceSet(asStored.F), CanonicalFaceSet(g.F));
  int flipped = -1;
  ASSERT_EQ(vcgext::ImportQuads(m, oriented, nullptr, &flipped), "");
  EXPECT_EQ(flipped, 2 * 3);
  EXPECT_EQ(CanonicalFaceSet(oriented.F), CanonicalFaceSet(Grid(4).F));
  vcgext::PolyData p;
  flipped = -1;
  ASSERT_EQ(vcgext::ImportPolygons(m, p, &flipped), "");
  EXPECT_EQ(flipped, 2 * 3);
  std::vector<std::vector<int>> grid;
  for (const auto& f : Grid(4).F) grid.push_back({f[0], f[1], f[2], f[3]});
  EXPECT_EQ(CanonicalFaceSet(p.F), CanonicalFaceSet(grid));
  ASSERT_EQ(vcgext::ImportQuads(m, asStored), "");  // the layer as it was
  EXPECT_EQ(CanonicalFaceSet(asStored.F), CanonicalFaceSet(g.F));

  // A Moebius strip of six quads (top i, bottom i + 6, the last quad joining the first twisted)
  // cannot be oriented: said so.
  vcgext::QuadData strip;
  for (int i = 0; i < 12; ++i) strip.V.emplace_back(std::cos(i % 6), std::sin(i % 6), i < 6 ? 0.1 * i : -1.0 - 0.1 * i);
  for (int i = 0; i < 6; ++i) strip.F.push_back({i, i + 6, i < 5 ? i + 7 : 0, i < 5 ? i + 1 : 6});
  vcgext::TMesh mm;
  vcgext::ExportQuads(strip, mm);
  EXPECT_NE(vcgext::ImportQuads(mm, asStored, nullptr, &flipped).find("the control layer is not orientable: 1 of its pieces"),
            std::string::npos);
}
