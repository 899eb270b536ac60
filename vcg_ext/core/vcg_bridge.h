#pragma once
/// \file vcg_bridge.h
/// Conversions between vcg layers and the plain arrays of indexed_mesh.h for polygonal data:
/// MeshLab stores a quad as two triangles whose shared edge is faux (`IsF`), so a pure-quad
/// layer is read by pairing triangles across their faux edge, and written the same way.
#include <Eigen/Core>
#include <array>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <vcg/complex/complex.h>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Reads a pure-quad vcg layer (triangle pairs with one faux edge each) into `out`.
/// Returns an empty string, or what is wrong: empty layer, NaN coordinates, a triangle with no
/// faux edge (not pure quads: how many), a polygon with more than four sides, a faux edge with
/// no matching partner, a faux edge used twice in the same direction (ambiguous pairing). Deleted elements are skipped; unreferenced vertices are kept.
template <class MeshType>
std::string ImportQuads(const MeshType& m, QuadData& out) {
  out.V.clear();
  out.F.clear();
  std::vector<int> remap(m.vert.size(), -1);
  int nonFinite = 0;
  for (size_t i = 0; i < m.vert.size(); ++i) {
    if (m.vert[i].IsD()) continue;
    const auto& p = m.vert[i].cP();
    Vec3 q{double(p[0]), double(p[1]), double(p[2])};
    if (!q.allFinite()) ++nonFinite;
    remap[i] = int(out.V.size());
    out.V.push_back(q);
  }
  if (out.V.empty()) return "the control layer is empty";
  if (nonFinite) return std::to_string(nonFinite) + " control vertices have NaN or infinite coordinates";
  // Faux edges keyed by their directed (from, to) pair; the partner has (to, from).
  std::map<std::pair<int, int>, int> fauxOf;
  std::vector<std::array<int, 3>> tris;
  std::vector<int> fauxSlot;
  int triangles = 0, polygons = 0, ambiguous = 0;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) t[k] = remap[f.cV(k) - &m.vert[0]];
    int nf = 0, slot = -1;
    for (int k = 0; k < 3; ++k)
      if (f.IsF(k)) { ++nf; slot = k; }
    if (nf == 0) { ++triangles; continue; }
    if (nf > 1) { ++polygons; continue; }
    if (!fauxOf.emplace(std::make_pair(t[slot], t[(slot + 1) % 3]), int(tris.size())).second) ++ambiguous;
    tris.push_back(t);
    fauxSlot.push_back(slot);
  }
  if (tris.empty() && triangles == 0) return "the control layer has no faces";
  if (triangles > 0)
    return "the control layer is not pure-quad: " + std::to_string(triangles) +
           " triangles have no faux edge (a quad is two triangles sharing a faux edge)";
  if (polygons > 0)
    return "the control layer is not pure-quad: " + std::to_string(polygons) +
           " faces belong to polygons with more than four sides";
  if (ambiguous > 0)
    return "the control layer's quads cannot be paired unambiguously: " + std::to_string(ambiguous) +
           " faux diagonals are shared by several triangles (non-manifold triangulation)";
  std::vector<char> done(tris.size(), 0);
  int unmatched = 0;
  for (size_t i = 0; i < tris.size(); ++i) {
    if (done[i]) continue;
    const auto& t = tris[i];
    int k = fauxSlot[i];
    int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
    auto it = fauxOf.find({b, a});
    if (it == fauxOf.end() || done[it->second] || size_t(it->second) == i) { ++unmatched; continue; }
    const auto& t2 = tris[it->second];
    int k2 = fauxSlot[it->second];
    int d = t2[(k2 + 2) % 3];
    done[i] = done[it->second] = 1;
    out.F.push_back({a, d, b, c});  // boundary a→d→b→c (the diagonal a–b removed)
  }
  if (unmatched > 0)
    return "the control layer is not pure-quad: " + std::to_string(unmatched) +
           " faux edges have no consistently oriented partner triangle";
  return "";
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
/// Two quads may share both ends of a diagonal (opposite corners a and c in both) or a diagonal
/// may join two vertices that also share a mesh edge: splitting along a–c there would give a
/// non-manifold triangle edge and an ambiguous pairing on import, so such a quad is split along
/// b–d instead (the pairing of ImportQuads is then unique). Returns the number of quads where
/// neither diagonal was free (0 on every mesh we produce; such a layer cannot be re-imported).
template <class MeshType>
int ExportQuads(const QuadData& q, MeshType& m,
                const std::vector<std::array<Eigen::Vector2d, 4>>* wedgeUV = nullptr) {
  m.Clear();
  auto vi = vcg::tri::Allocator<MeshType>::AddVertices(m, q.V.size());
  for (size_t i = 0; i < q.V.size(); ++i, ++vi)
    for (int k = 0; k < 3; ++k) vi->P()[k] = typename MeshType::ScalarType(q.V[i][k]);
  auto key = [](int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); };
  std::set<std::pair<int, int>> used;  // undirected mesh edges and chosen diagonals
  for (const auto& f : q.F)
    for (int k = 0; k < 4; ++k) used.insert(key(f[k], f[(k + 1) % 4]));
  int blocked = 0;
  auto fi = vcg::tri::Allocator<MeshType>::AddFaces(m, 2 * q.F.size());
  for (size_t i = 0; i < q.F.size(); ++i) {
    const auto& f = q.F[i];
    int s = 0;  // first corner of the diagonal: 0 (a–c) or 1 (b–d)
    if (used.count(key(f[0], f[2]))) {
      if (!used.count(key(f[1], f[3]))) s = 1;
      else ++blocked;
    }
    used.insert(key(f[s], f[s + 2]));
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
