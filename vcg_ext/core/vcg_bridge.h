#pragma once
/// \file vcg_bridge.h
/// Conversions between vcg layers and the plain arrays of indexed_mesh.h for polygonal data:
/// MeshLab stores a quad as two triangles whose shared edge is faux (`IsF`), so a pure-quad
/// layer is read by pairing triangles across their faux edge, and written the same way.
#include <Eigen/Core>
#include <array>
#include <algorithm>
#include <functional>
#include <map>
#include <tuple>
#include <string>
#include <vector>

#include <vcg/complex/complex.h>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Reads a pure-quad vcg layer (triangle pairs with one faux edge each) into `out`.
/// Returns an empty string, or what is wrong: empty layer, NaN coordinates, a triangle with no
/// faux edge (not pure quads: how many), a polygon with more than four sides, a faux edge with
/// no matching partner. Deleted elements are skipped; unreferenced vertices are kept.
/// A faux diagonal shared by several triangle pairs (two quads with the same opposite corners,
/// split along them by a tool that fans polygons, e.g. MeshLab's PLY importer) is ambiguous:
/// those triangles are paired greedily by the agreement of their normals (a true quad's two
/// halves are nearly coplanar); `ambiguousResolved` (optional) counts such diagonals.
template <class MeshType>
std::string ImportQuads(const MeshType& m, QuadData& out, int* ambiguousResolved = nullptr) {
  if (ambiguousResolved) *ambiguousResolved = 0;
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
  std::map<std::pair<int, int>, std::vector<int>> fauxOf;
  std::vector<std::array<int, 3>> tris;
  std::vector<int> fauxSlot;
  int triangles = 0, polygons = 0;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) t[k] = remap[f.cV(k) - &m.vert[0]];
    int nf = 0, slot = -1;
    for (int k = 0; k < 3; ++k)
      if (f.IsF(k)) { ++nf; slot = k; }
    if (nf == 0) { ++triangles; continue; }
    if (nf > 1) { ++polygons; continue; }
    fauxOf[{t[slot], t[(slot + 1) % 3]}].push_back(int(tris.size()));
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
  auto normal = [&](int i) {
    const auto& t = tris[i];
    Vec3 n = (out.V[t[1]] - out.V[t[0]]).cross(out.V[t[2]] - out.V[t[0]]);
    double l = n.norm();
    return l > 0 ? Vec3(n / l) : Vec3::Zero();
  };
  std::vector<char> done(tris.size(), 0);
  int unmatched = 0;
  std::vector<std::pair<int, int>> twoByTwo;  // ambiguous diagonals shared by exactly two quads
  for (const auto& [key, side] : fauxOf) {
    if (key.first > key.second) continue;  // each diagonal once, from its (low, high) side
    auto it = fauxOf.find({key.second, key.first});
    const size_t n2 = it == fauxOf.end() ? 0 : it->second.size();
    if (n2 == 0) continue;
    const std::vector<int>& other = it->second;
    if (side.size() > 1 || n2 > 1)
      if (ambiguousResolved) ++*ambiguousResolved;
    // greedy matching by normal agreement (trivial for the usual 1:1 case)
    std::vector<std::tuple<double, int, int>> cand;
    for (int i : side)
      for (int j : other) cand.emplace_back(-normal(i).dot(normal(j)), i, j);
    std::sort(cand.begin(), cand.end());
    if (side.size() == 2 && n2 == 2) twoByTwo.emplace_back(int(out.F.size()), int(out.F.size()) + 1);
    for (const auto& [score, i, j] : cand) {
      if (done[i] || done[j]) continue;
      done[i] = done[j] = 1;
      const auto& t = tris[i];
      const int k = fauxSlot[i];
      const int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
      const int d = tris[j][(fauxSlot[j] + 2) % 3];
      out.F.push_back({a, d, b, c});  // boundary a→d→b→c (the diagonal a–b removed)
    }
  }
  for (size_t i = 0; i < tris.size(); ++i) unmatched += !done[i];
  // Normals can mislead (folded regions); the pairing that is wrong splits the quad fan of a
  // diagonal end into two (a non-manifold vertex). For diagonals shared by two quads, keep the
  // pairing with fewer fans at the diagonal's ends (two passes: groups can share vertices).
  if (!twoByTwo.empty()) {
    std::map<int, std::vector<int>> quadsAt;
    for (const auto& [q1, q2] : twoByTwo)
      for (int q : {q1, q2})
        for (int c = 0; c < 4; ++c) quadsAt[out.F[q][c]];
    for (size_t f = 0; f < out.F.size(); ++f)
      for (int c = 0; c < 4; ++c) {
        auto it = quadsAt.find(out.F[f][c]);
        if (it != quadsAt.end()) it->second.push_back(int(f));
      }
    auto fans = [&](int v) {  // components of the corner graph (prev–next neighbour) at v
      std::map<int, int> parent;
      std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
      for (int f : quadsAt[v])
        for (int c = 0; c < 4; ++c)
          if (out.F[f][c] == v) {
            int p = out.F[f][(c + 3) % 4], n = out.F[f][(c + 1) % 4];
            if (!parent.count(p)) parent[p] = p;
            if (!parent.count(n)) parent[n] = n;
            parent[find(p)] = find(n);
          }
      int k = 0;
      for (const auto& [x, px] : parent) k += find(x) == x;
      return k;
    };
    auto swapD = [&](int q1, int q2) {  // exchange the d corners, keeping quadsAt current
      const int d1 = out.F[q1][1], d2 = out.F[q2][1];
      auto& l1 = quadsAt[d1];
      auto& l2 = quadsAt[d2];
      for (int& f : l1) if (f == q1) f = q2;
      for (int& f : l2) if (f == q2) f = q1;
      std::swap(out.F[q1][1], out.F[q2][1]);
    };
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& [q1, q2] : twoByTwo) {
        const int a = out.F[q1][0], b = out.F[q1][2];
        const int before = fans(a) + fans(b);
        swapD(q1, q2);
        if (fans(a) + fans(b) >= before) swapD(q1, q2);
      }
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
