/// \file loop_local_subdivision.cpp
/// Local Loop subdivision of a net (§3.2): vertex and edge points by the smooth and crease rules
/// (hard edges and vertices by the 1-D spline rules, §2.4), the children's nets, and the
/// self-similar rings that replace the subdivision below the cache depth.
#include "vcg_ext/loop/loop_net.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace vcgext::loop_internal {

double LoopBeta(int k) {
  double t = 0.375 + 0.25 * std::cos(2.0 * M_PI / k);
  return (0.625 - t * t) / k;
}

namespace {

// Smooth Loop vertex point of c: (1 - k beta) c + beta * (sum of its k ring vertices).
Vec3 SmoothVertexPoint(const LNet& n, int c) {
  Vec3 sum = Vec3::Zero();
  int val = 0;
  for (size_t f = 0; f < n.F.size(); ++f)
    for (int j = 0; j < 3; ++j)
      if (n.F[f][j] == c) {
        ++val;
        sum += n.P[n.F[f][(j + 1) % 3]];  // each ring vertex once (closed fan)
      }
  double b = LoopBeta(val);
  return (1.0 - val * b) * n.P[c] + b * sum;
}

// Crease vertex point of c: (a + 6 c + b) / 8 with its two distinct hard neighbours, else c.
Vec3 CreaseVertexPoint(const LNet& n, int c) {
  // each hard edge seen from both of its faces, except on a boundary: average distinct ones
  Vec3 hs = Vec3::Zero();
  int cnt = 0;
  int seen[4], ns = 0;
  for (size_t f = 0; f < n.F.size(); ++f)
    for (int j = 0; j < 3; ++j)
      if (n.F[f][j] == c) {
        int cands[2] = {n.H[f][j] ? n.F[f][(j + 1) % 3] : -1, n.H[f][(j + 2) % 3] ? n.F[f][(j + 2) % 3] : -1};
        for (int o : cands) {
          if (o < 0) continue;
          bool dup = false;
          for (int s = 0; s < ns; ++s) dup |= seen[s] == o;
          if (!dup && ns < 4) { seen[ns++] = o; hs += n.P[o]; ++cnt; }
        }
      }
  return cnt == 2 ? Vec3((hs + 6.0 * n.P[c]) / 8.0) : n.P[c];
}

// Vertex point of corner c by its type (smooth rule, crease rule; hard vertices stay fixed).
Vec3 VertexPoint(const LNet& n, int c) {
  const unsigned char t = n.type[c];
  if (t == (unsigned char)LoopVertexType::Smooth) return SmoothVertexPoint(n, c);
  if (t == (unsigned char)LoopVertexType::Crease) return CreaseVertexPoint(n, c);
  return n.P[c];
}

// Whether v is a corner of T.
inline bool IsCornerOf(const Tri& T, int v) { return v == T[0] || v == T[1] || v == T[2]; }

// The edge points of one subdivision step: one new vertex per edge touching a target corner.
struct EdgePoints {
  struct E { int a, b, id; };
  std::vector<E> edges;
  // edge (a < b) -> new vertex id; a hash map, not a scan of `edges`: the net round a vertex of
  // valence N has ~N such edges and ~2N faces, so a scan made each step O(N^2)
  std::unordered_map<int64_t, int> ids;
  std::vector<Vec3> opp;             ///< per edge point: sum of the opposite vertices
  std::vector<int> oppCount;         ///< per edge point: faces seen
  std::vector<unsigned char> ehard;  ///< per edge point: the edge is hard
  int nv = 0;                        ///< vertices of the coarse net (key stride)
  // Key of the undirected edge (a, b).
  int64_t Key(int a, int b) const { return int64_t(std::min(a, b)) * nv + std::max(a, b); }
  // New vertex id of edge (a, b), -1 if not registered.
  int Id(int a, int b) const {
    const auto it = ids.find(Key(a, b));
    return it == ids.end() ? -1 : it->second;
  }
};

// Registers the edges touching a target corner (new vertices of `out`), summing opposite vertices.
void CollectEdges(const LNet& n, const Tri& T, EdgePoints& ep, LNet& out) {
  ep.nv = int(n.P.size());
  ep.ids.reserve(2 * n.F.size());
  for (size_t f = 0; f < n.F.size(); ++f)
    for (int j = 0; j < 3; ++j) {
      int a = n.F[f][j], b = n.F[f][(j + 1) % 3], o = n.F[f][(j + 2) % 3];
      if (!IsCornerOf(T, a) && !IsCornerOf(T, b)) continue;
      int id = ep.Id(a, b);
      if (id < 0) {
        id = int(out.P.size());
        ep.edges.push_back({std::min(a, b), std::max(a, b), id});
        ep.ids.emplace(ep.Key(a, b), id);
        out.P.push_back(Vec3::Zero());
        out.type.push_back(n.H[f][j] ? (unsigned char)LoopVertexType::Crease : (unsigned char)LoopVertexType::Smooth);
        ep.opp.push_back(Vec3::Zero());
        ep.oppCount.push_back(0);
        ep.ehard.push_back(n.H[f][j]);
      }
      int e = id - 3;
      ep.opp[e] += n.P[o];
      ep.oppCount[e]++;
      ep.ehard[e] |= n.H[f][j];
    }
}

// Places the edge points: midpoint on hard or boundary edges, else 3/8 (a + b) + 1/8 (opposites).
void PlaceEdgePoints(const LNet& n, const EdgePoints& ep, LNet& out) {
  for (const EdgePoints::E& e : ep.edges) {
    int k = e.id - 3;
    if (ep.ehard[k] || ep.oppCount[k] != 2) out.P[e.id] = 0.5 * (n.P[e.a] + n.P[e.b]);
    else out.P[e.id] = 0.375 * (n.P[e.a] + n.P[e.b]) + 0.125 * ep.opp[k];
    out.type[e.id] = ep.ehard[k] ? (unsigned char)LoopVertexType::Crease : (unsigned char)LoopVertexType::Smooth;
  }
}

// Corners of sub-triangle `child` (0..2 at corner c_child, 3 middle) as new vertex ids.
Tri ChildTriangle(const Tri& T, const int vp[3], const EdgePoints& ep, int child) {
  int e01 = ep.Id(T[0], T[1]), e12 = ep.Id(T[1], T[2]), e20 = ep.Id(T[2], T[0]);
  Tri ct;
  switch (child) {
    case 0: ct = {vp[0], e01, e20}; break;
    case 1: ct = {vp[1], e12, e01}; break;
    case 2: ct = {vp[2], e20, e12}; break;
    default: ct = {e12, e20, e01}; break;
  }
  return ct;
}

// Faces of the child's net (new vertex ids) and which one is its target.
struct ChildFaces {
  std::vector<Tri> F;
  std::vector<std::array<unsigned char, 3>> H;
  int target = -1;
};

// Keeps fine face t (hard flags h) if complete and touching a corner of ct; the target in ct's order.
void AddChildFace(const Tri& ct, Tri t, std::array<unsigned char, 3> h, ChildFaces& cf) {
  auto isChildCorner = [&](int v) { return v == ct[0] || v == ct[1] || v == ct[2]; };
  if (t[0] < 0 || t[1] < 0 || t[2] < 0) return;
  if (!isChildCorner(t[0]) && !isChildCorner(t[1]) && !isChildCorner(t[2])) return;
  // target face: rotate to ct order
  for (int r = 0; r < 3; ++r)
    if (t[r] == ct[0] && t[(r + 1) % 3] == ct[1] && t[(r + 2) % 3] == ct[2]) {
      Tri tt = {t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
      std::array<unsigned char, 3> hh = {h[r], h[(r + 1) % 3], h[(r + 2) % 3]};
      cf.target = int(cf.F.size());
      cf.F.push_back(tt);
      cf.H.push_back(hh);
      return;
    }
  cf.F.push_back(t);
  cf.H.push_back(h);
}

// Vertex point id of target corner v, -1 if v is not a corner.
int VertexPointOf(const Tri& T, const int vp[3], int v) {
  for (int k = 0; k < 3; ++k)
    if (T[k] == v) return vp[k];
  return -1;
}

// Splits each coarse face into its 4 children and keeps those touching the child triangle ct.
void BuildChildFaces(const LNet& n, const Tri& T, const int vp[3], const EdgePoints& ep, const Tri& ct,
                     ChildFaces& cf) {
  for (size_t f = 0; f < n.F.size(); ++f) {
    int a = n.F[f][0], b = n.F[f][1], c = n.F[f][2];
    const bool ca = IsCornerOf(T, a), cb = IsCornerOf(T, b), cc = IsCornerOf(T, c);
    int eab = (ca || cb) ? ep.Id(a, b) : -1;
    int ebc = (cb || cc) ? ep.Id(b, c) : -1;
    int eca = (cc || ca) ? ep.Id(c, a) : -1;
    const auto& h = n.H[f];
    if (ca) AddChildFace(ct, {VertexPointOf(T, vp, a), eab, eca}, {h[0], 0, h[2]}, cf);
    if (cb) AddChildFace(ct, {VertexPointOf(T, vp, b), ebc, eab}, {h[1], 0, h[0]}, cf);
    if (cc) AddChildFace(ct, {VertexPointOf(T, vp, c), eca, ebc}, {h[2], 0, h[1]}, cf);
    AddChildFace(ct, {eab, ebc, eca}, {0, 0, 0}, cf);
  }
}

// The child's net: the vertices of `fine` its faces use, renumbered in order of first use.
LNet CompactNet(const LNet& fine, const ChildFaces& cf) {
  std::vector<int> remap(fine.P.size(), -1);
  LNet res;
  for (const Tri& t : cf.F)
    for (int k = 0; k < 3; ++k)
      if (remap[t[k]] < 0) {
        remap[t[k]] = int(res.P.size());
        res.P.push_back(fine.P[t[k]]);
        res.type.push_back(fine.type[t[k]]);
      }
  res.F.resize(cf.F.size());
  for (size_t f = 0; f < cf.F.size(); ++f)
    for (int k = 0; k < 3; ++k) res.F[f][k] = remap[cf.F[f][k]];
  res.H = cf.H;
  res.target = cf.target;
  return res;
}

}  // namespace

/// One step of local Loop subdivision: the net of sub-triangle `child` (0..2 corner c_child, 3 middle).
LNet Subdivide(const LNet& n, int child) {
  const Tri T = n.F[n.target];
  LNet out;  // vertex points of the corners (ids 0..2), then edge points of edges touching a corner
  int vp[3];
  for (int k = 0; k < 3; ++k) {
    vp[k] = int(out.P.size());
    out.P.push_back(VertexPoint(n, T[k]));
    out.type.push_back(n.type[T[k]]);
  }
  EdgePoints ep;
  CollectEdges(n, T, ep, out);
  PlaceEdgePoints(n, ep, out);
  const Tri ct = ChildTriangle(T, vp, ep, child);
  ChildFaces cf;
  BuildChildFaces(n, T, vp, ep, ct, cf);
  return CompactNet(out, cf);
}

std::string TopologyKey(const LNet& n) {
  std::string k;
  k.reserve(16 + n.F.size() * 15 + n.type.size());
  auto put = [&](int x) { k.append(reinterpret_cast<const char*>(&x), sizeof(int)); };
  put(int(n.P.size()));
  put(n.target);
  for (size_t f = 0; f < n.F.size(); ++f) {
    for (int c = 0; c < 3; ++c) put(n.F[f][c]);
    for (int c = 0; c < 3; ++c) k.push_back(char(n.H[f][c]));
  }
  for (unsigned char t : n.type) k.push_back(char(t));
  return k;
}

/// Builds the Ring of a net, or returns false when the net is not self-similar.
bool BuildRing(const LNet& net, Ring& r) {
  const int n = int(net.P.size());
  if (n > 96) return false;
  Vec3 X[12];
  for (int kc = 0; kc < 3; ++kc) {
    LNet ch = Subdivide(net, kc);
    if (ch.F != net.F || ch.H != net.H || ch.type != net.type || ch.target != net.target || ch.P.size() != net.P.size()) continue;
    bool ok = true;
    for (int c = 0; c < 4 && ok; ++c)
      if (c != kc) ok = Gather(Subdivide(net, c), X);
    if (!ok) continue;
    r.n = n;
    r.kc = kc;
    r.S.assign(size_t(n) * n, 0.0);
    for (int c = 0; c < 4; ++c)
      if (c != kc) r.T[c].assign(size_t(12) * n, 0.0);
    // columns by linearity: three unit vectors per pass (one per coordinate)
    LNet b = net;
    for (int j0 = 0; j0 < n; j0 += 3) {
      for (int i = 0; i < n; ++i) b.P[i] = Vec3(i == j0, i == j0 + 1, i == j0 + 2);
      LNet sb = Subdivide(b, kc);
      for (int i = 0; i < n; ++i)
        for (int d = 0; d < 3 && j0 + d < n; ++d) r.S[size_t(i) * n + j0 + d] = sb.P[i][d];
      for (int c = 0; c < 4; ++c) {
        if (c == kc) continue;
        if (!Gather(Subdivide(b, c), X)) return false;
        for (int m = 0; m < 12; ++m)
          for (int d = 0; d < 3 && j0 + d < n; ++d) r.T[c][size_t(m) * n + j0 + d] = X[m][d];
      }
    }
    return true;
  }
  return false;
}

}  // namespace vcgext::loop_internal
