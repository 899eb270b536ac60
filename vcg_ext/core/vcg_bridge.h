#pragma once
/// \file vcg_bridge.h
/// Conversions between vcg layers and the plain arrays of indexed_mesh.h for polygonal data:
/// MeshLab stores a quad as two triangles whose shared edge is faux (`IsF`), so a pure-quad
/// layer is read by pairing triangles across their faux edge, and written the same way.
#include <Eigen/Core>
#include <array>
#include <algorithm>
#include <string>
#include <vector>

#include <vcg/complex/complex.h>

#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/quad_pairing.h"

namespace vcgext {

namespace bridge_detail {
// The live vertices of `m` into V; remap (vertex index of `m` -> index in V, -1 for deleted).
// "" or what is wrong (empty layer, NaN coordinates).
template <class MeshType>
std::string ImportLayerVertices(const MeshType& m, std::vector<Vec3>& V, std::vector<int>& remap) {
  V.clear();
  remap.assign(m.vert.size(), -1);
  int nonFinite = 0;
  for (size_t i = 0; i < m.vert.size(); ++i) {
    if (m.vert[i].IsD()) continue;
    const auto& p = m.vert[i].cP();
    Vec3 q{double(p[0]), double(p[1]), double(p[2])};
    if (!q.allFinite()) ++nonFinite;
    remap[i] = int(V.size());
    V.push_back(q);
  }
  if (V.empty()) return "the control layer is empty";
  if (nonFinite) return std::to_string(nonFinite) + " control vertices have NaN or infinite coordinates";
  return "";
}

// The live vertices (ImportLayerVertices) and triangles of `m` with their faux flags; with
// `flipped`, the triangles oriented coherently first (OrientFauxTriangles), *flipped the number
// flipped. "" or what is wrong (as ImportLayerVertices, no faces, a component that cannot be oriented).
template <class MeshType>
std::string ImportLayerTriangles(const MeshType& m, std::vector<Vec3>& V, FauxTriangles& t, int* flipped) {
  std::vector<int> remap;
  std::string err = ImportLayerVertices(m, V, remap);
  if (!err.empty()) return err;
  t = FauxTriangles();
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    t.tris.push_back({remap[f.cV(0) - &m.vert[0]], remap[f.cV(1) - &m.vert[0]], remap[f.cV(2) - &m.vert[0]]});
    t.faux.push_back({f.IsF(0), f.IsF(1), f.IsF(2)});
  }
  if (t.tris.empty()) return "the control layer has no faces";
  if (!flipped) return "";
  int nonOrientable = 0;
  *flipped = OrientFauxTriangles(t, &nonOrientable);
  if (nonOrientable > 0)
    return "the control layer is not orientable: " + std::to_string(nonOrientable) +
           " of its pieces cannot be oriented coherently (a Moebius strip)";
  return "";
}
}  // namespace bridge_detail

/// Reads a pure-quad vcg layer (triangle pairs with one faux edge each) into `out`.
/// Returns an empty string, or what is wrong: empty layer, NaN coordinates, a triangle with no
/// faux edge (not pure quads: how many), a polygon with more than four sides, a faux edge with
/// no matching partner. Deleted elements are skipped; unreferenced vertices are kept.
/// A faux diagonal shared by several triangle pairs (two quads with the same opposite corners,
/// split along them by a tool that fans polygons, e.g. MeshLab's PLY importer) is ambiguous:
/// those triangles are paired greedily by the agreement of their normals (a true quad's two
/// halves are nearly coplanar); `ambiguousResolved` (optional) counts such diagonals.
/// With `flipped` (optional), the layer's triangles are first oriented coherently, each piece
/// keeping its majority's orientation (OrientFauxTriangles), and *flipped counts those flipped
/// (the layer is not modified); a piece that cannot be oriented is then an error.
template <class MeshType>
std::string ImportQuads(const MeshType& m, QuadData& out, int* ambiguousResolved = nullptr, int* flipped = nullptr) {
  if (ambiguousResolved) *ambiguousResolved = 0;
  out.F.clear();
  FauxTriangles t;
  std::string err = bridge_detail::ImportLayerTriangles(m, out.V, t, flipped);
  if (!err.empty()) return err;
  FauxHalves halves;
  int triangles = 0, polygons = 0;
  for (size_t i = 0; i < t.tris.size(); ++i) {
    const auto& faux = t.faux[i];
    const int nf = int(faux[0]) + int(faux[1]) + int(faux[2]);
    if (nf == 0) { ++triangles; continue; }
    if (nf > 1) { ++polygons; continue; }
    halves.tris.push_back(t.tris[i]);
    halves.fauxSlot.push_back(faux[0] ? 0 : faux[1] ? 1 : 2);
  }
  if (triangles > 0)
    return "the control layer is not pure-quad: " + std::to_string(triangles) +
           " triangles have no faux edge (a quad is two triangles sharing a faux edge)";
  if (polygons > 0)
    return "the control layer is not pure-quad: " + std::to_string(polygons) +
           " faces belong to polygons with more than four sides";
  return PairFauxHalves(halves, out, ambiguousResolved);
}

/// Reads a polygonal vcg layer (MeshLab's convention: the triangles of one polygon joined by faux
/// edges) into `out`: triangles, quads and n-gons (PolygonsFromFauxTriangles). Returns "" or what
/// is wrong (as ImportQuads, or faux edges that do not make polygons). Deleted elements are
/// skipped; unreferenced vertices are kept. Unlike ImportQuads, a faux edge shared by several
/// triangle pairs is refused rather than resolved. `flipped` as for ImportQuads.
template <class MeshType>
std::string ImportPolygons(const MeshType& m, PolyData& out, int* flipped = nullptr) {
  out.F.clear();
  FauxTriangles t;
  std::string err = bridge_detail::ImportLayerTriangles(m, out.V, t, flipped);
  if (!err.empty()) return err;
  err = PolygonsFromFauxTriangles(t, out.F);
  return err.empty() ? err : "the control layer's polygons cannot be read: " + err;
}

/// Appends nothing, replaces `m`'s content with the triangles of `d` and, if given, a
/// per-vertex quality (`MeshType` must have vertex quality then).
template <class MeshType>
void ExportTriangles(const TriData& d, MeshType& m, const std::vector<double>* quality = nullptr) {
  m.Clear();
  auto vi = vcg::tri::Allocator<MeshType>::AddVertices(m, d.V.size());
  for (size_t i = 0; i < d.V.size(); ++i, ++vi) {
    for (int k = 0; k < 3; ++k) vi->P()[k] = typename MeshType::ScalarType(d.V[i][k]);
    if (quality) vi->Q() = typename MeshType::VertexType::QualityType((*quality)[i]);
  }
  auto fi = vcg::tri::Allocator<MeshType>::AddFaces(m, d.F.size());
  for (size_t i = 0; i < d.F.size(); ++i, ++fi)
    for (int k = 0; k < 3; ++k) fi->V(k) = &m.vert[d.F[i][k]];
}

/// Replaces `m`'s content with the quads of `q` in MeshLab's polygonal convention: quad
/// (a,b,c,d) becomes triangles (a,b,c) and (a,c,d) with the diagonal a–c faux. If `wedgeUV` is
/// given (one (u,v) per quad corner), it is written to the wedge texture coordinates with
/// texture index 0 (`MeshType` must have wedge texcoords enabled then).
/// Where a–c is not free (FreeDiagonalStarts: another quad's diagonal or a mesh edge, which
/// would give a non-manifold triangle edge and an ambiguous pairing) the quad is split along b–d.
/// Returns the number of quads where neither diagonal was free.
template <class MeshType>
int ExportQuads(const QuadData& q, MeshType& m,
                const std::vector<std::array<Eigen::Vector2d, 4>>* wedgeUV = nullptr) {
  m.Clear();
  auto vi = vcg::tri::Allocator<MeshType>::AddVertices(m, q.V.size());
  for (size_t i = 0; i < q.V.size(); ++i, ++vi)
    for (int k = 0; k < 3; ++k) vi->P()[k] = typename MeshType::ScalarType(q.V[i][k]);
  int blocked = 0;
  const std::vector<int> start = FreeDiagonalStarts(q, &blocked);
  auto fi = vcg::tri::Allocator<MeshType>::AddFaces(m, 2 * q.F.size());
  for (size_t i = 0; i < q.F.size(); ++i) {
    const auto& f = q.F[i];
    const int s = start[i];  // the diagonal s–(s+2) is faux
    const int corners[2][3] = {{s, s + 1, s + 2}, {s, s + 2, (s + 3) % 4}};
    for (int h = 0; h < 2; ++h, ++fi) {
      for (int k = 0; k < 3; ++k) {
        fi->V(k) = &m.vert[f[corners[h][k]]];
        if (wedgeUV) {
          const auto& uv = (*wedgeUV)[i][corners[h][k]];
          fi->WT(k).U() = typename MeshType::ScalarType(uv[0]);
          fi->WT(k).V() = typename MeshType::ScalarType(uv[1]);
          fi->WT(k).N() = 0;
        }
      }
      fi->ClearAllF();
      fi->SetF(h == 0 ? 2 : 0);  // the diagonal: edge 2 (c→a) of the first, 0 (a→c) of the second
    }
  }
  return blocked;
}

}  // namespace vcgext
