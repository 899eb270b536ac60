#include "vcg_ext/quad/quad_mesh.h"
#include "vcg_ext/core/union_find.h"

#include <algorithm>
#include <cstdint>

namespace vcgext {
namespace quad {

const char* ToString(OpResult r) {
  switch (r) {
    case OpResult::Ok: return "ok";
    case OpResult::DeadElement: return "dead element";
    case OpResult::BoundaryMerge: return "would merge two boundary vertices";
    case OpResult::BoundaryEdge: return "boundary edge";
    case OpResult::NotDoublet: return "not a doublet";
    case OpResult::Degenerate: return "would create a degenerate face";
    case OpResult::NonManifold: return "would break manifoldness (link condition)";
    case OpResult::LowValence: return "would create a low-valence vertex";
    case OpResult::NoImprovement: return "no valence improvement";
  }
  return "?";
}

QuadMesh::QuadMesh(const std::vector<Vec3>& V, const std::vector<Quad>& Fin) : P(V), F(Fin) {
  faceAlive_.assign(F.size(), 1);
  vertAlive_.assign(P.size(), 1);
  vf_.assign(P.size(), {});
  for (size_t f = 0; f < F.size(); ++f)
    for (int k = 0; k < 4; ++k) {
      auto& l = vf_[F[f][k]];
      if (std::find(l.begin(), l.end(), int(f)) == l.end()) l.push_back(int(f));
    }
  nFaces_ = int(F.size());
  nVerts_ = 0;
  boundary_.assign(P.size(), 0);
  std::vector<Wedge> w;
  for (size_t v = 0; v < P.size(); ++v) {
    if (vf_[v].empty()) { vertAlive_[v] = 0; continue; }  // unreferenced: not part of K
    ++nVerts_;
    bool open = false;
    Fan(int(v), w, &open);
    boundary_[v] = open ? 1 : 0;
  }
}

int QuadMesh::CornerOf(int f, int v) const {
  for (int k = 0; k < 4; ++k)
    if (F[f][k] == v) return k;
  return -1;
}

Vec3 QuadMesh::Centroid(int f) const {
  return 0.25 * (P[F[f][0]] + P[F[f][1]] + P[F[f][2]] + P[F[f][3]]);
}

// Fan's ordering of its m wedges w (each corner's f, k, n, o, p), with the checks: every n and every
// p once (each directed edge once), at most one wedge whose p is no wedge's n (the start of an open
// fan; a closed fan starts at wedge 0), and the chain from the start through all m wedges, each
// next wedge the one whose p is the current one's n. The wedge with a given n or p is found by a
// scan in small fans and, above valence kSmallFan (a pole, a vertex that took many collapses), by
// look-ups in sorted arrays: O(m log m) instead of O(m^2), the same order.
namespace {
constexpr int kSmallFan = 16;
bool OrderFan(const Wedge* w, int m, std::vector<Wedge>& out, bool* open) {
  const bool large = m > kSmallFan;
  std::vector<std::pair<int, int>> byP, byN;  // large: (vertex, wedge), sorted
  if (large) {
    for (int i = 0; i < m; ++i) byP.push_back({w[i].p, i}), byN.push_back({w[i].n, i});
    std::sort(byP.begin(), byP.end());
    std::sort(byN.begin(), byN.end());
    for (size_t i = 1; i < size_t(m); ++i)
      if (byP[i].first == byP[i - 1].first || byN[i].first == byN[i - 1].first) return false;
  } else {
    for (int i = 0; i < m; ++i)
      for (int j = i + 1; j < m; ++j)
        if (w[i].n == w[j].n || w[i].p == w[j].p) return false;
  }
  auto withP = [&](bool p, int v) {  // the wedge whose p (else n) is v, or -1
    if (large) {
      const auto& by = p ? byP : byN;
      const auto it = std::lower_bound(by.begin(), by.end(), std::make_pair(v, -1));
      return it != by.end() && it->first == v ? it->second : -1;
    }
    for (int j = 0; j < m; ++j)
      if ((p ? w[j].p : w[j].n) == v) return j;
    return -1;
  };
  int start = -1, starts = 0;
  for (int i = 0; i < m; ++i)
    if (withP(false, w[i].p) < 0) { start = i; ++starts; }
  if (starts > 1) return false;
  const bool isOpen = starts == 1;
  if (!isOpen) start = 0;
  out.reserve(size_t(m));
  int cur = start;
  for (int step = 0; step < m; ++step) {
    out.push_back(w[cur]);
    const int nxt = withP(true, w[cur].n);
    if (step == m - 1) {
      if (isOpen ? nxt != -1 : nxt != start) return false;
    } else {
      if (nxt < 0 || nxt == start) return false;
      cur = nxt;
    }
  }
  if (open) *open = isOpen;
  return true;
}
}  // namespace

bool QuadMesh::Fan(int v, std::vector<Wedge>& out, bool* open) const {
  out.clear();
  const auto& l = vf_[v];
  const int m = int(l.size());
  if (open) *open = false;
  if (m == 0) return false;
  Wedge tmp[64];
  std::vector<Wedge> big;
  Wedge* w = tmp;
  if (m > 64) { big.resize(m); w = big.data(); }
  for (int i = 0; i < m; ++i) {
    const int f = l[i];
    const Quad& q = F[f];
    const int k = q[0] == v ? 0 : q[1] == v ? 1 : q[2] == v ? 2 : q[3] == v ? 3 : -1;
    if (k < 0) return false;
    w[i] = {f, k, q[(k + 1) & 3], q[(k + 2) & 3], q[(k + 3) & 3]};
  }
  return OrderFan(w, m, out, open);
}

int QuadMesh::AcrossEdge(int f, int k) const {
  int a = F[f][k], b = F[f][(k + 1) & 3];
  for (int g : vf_[a]) {
    if (g == f) continue;
    int kb = CornerOf(g, b);
    if (kb >= 0 && F[g][(kb + 1) & 3] == a) return g;
  }
  return -1;
}

// ---------------------------------------------------------------------------- journal
void QuadMesh::SaveFace(int f) { fj_.push_back({f, F[f], faceAlive_[f]}); }
void QuadMesh::SaveVert(int v) { vj_.push_back({v, P[v], vertAlive_[v], false, vf_[v]}); }

void QuadMesh::Begin() {
  fj_.clear();
  vj_.clear();
  recording_ = true;
}
void QuadMesh::Commit() {
  fj_.clear();
  vj_.clear();
  recording_ = false;
}
void QuadMesh::Rollback() {
  RollbackTo(0, 0);
  recording_ = false;
}
void QuadMesh::RollbackTo(size_t fmark, size_t vmark) {
  while (fj_.size() > fmark) {
    const FaceRec& r = fj_.back();
    if (faceAlive_[r.f] != r.alive) nFaces_ += r.alive ? 1 : -1;
    F[r.f] = r.q;
    faceAlive_[r.f] = r.alive;
    fj_.pop_back();
  }
  while (vj_.size() > vmark) {
    VertRec& r = vj_.back();
    P[r.v] = r.p;
    if (r.posOnly) { vj_.pop_back(); continue; }
    if (vertAlive_[r.v] != r.alive) nVerts_ += r.alive ? 1 : -1;
    vertAlive_[r.v] = r.alive;
    vf_[r.v].swap(r.vf);
    vj_.pop_back();
  }
}
void QuadMesh::EndOp(size_t fmark, size_t vmark, bool ok) {
  if (!ok) RollbackTo(fmark, vmark);
  if (!recording_) { fj_.clear(); vj_.clear(); }
}
void QuadMesh::MoveVertex(int v, const Vec3& p) {
  if (recording_) vj_.push_back({v, P[v], vertAlive_[v], true, {}});  // position only: no allocation
  P[v] = p;
}

void QuadMesh::RemoveVF(int v, int f) {
  auto& l = vf_[v];
  auto it = std::find(l.begin(), l.end(), f);
  if (it != l.end()) { *it = l.back(); l.pop_back(); }
}
void QuadMesh::KillFace(int f) {
  for (int k = 0; k < 4; ++k) RemoveVF(F[f][k], f);
  faceAlive_[f] = 0;
  --nFaces_;
}

OpResult QuadMesh::LocalCheck(const std::vector<int>& verts, bool allowDoublets) const {
  std::vector<Wedge> w;
  for (int v : verts) {
    if (!vertAlive_[v]) continue;
    if (vf_[v].empty()) return OpResult::LowValence;
    for (int f : vf_[v]) {
      const Quad& q = F[f];
      if (q[0] == q[1] || q[0] == q[2] || q[0] == q[3] || q[1] == q[2] || q[1] == q[3] || q[2] == q[3])
        return OpResult::Degenerate;
    }
    bool open = false;
    if (!Fan(v, w, &open)) return OpResult::NonManifold;
    if (open != (boundary_[v] != 0)) return OpResult::NonManifold;
    if (!boundary_[v] && Valence(v) < (allowDoublets ? 2 : 3)) return OpResult::LowValence;
  }
  return OpResult::Ok;
}

// ---------------------------------------------------------------------------- operators
OpResult QuadMesh::CollapseDiagonal(int f, int k, int* survivor) {
  if (f < 0 || f >= int(F.size()) || !faceAlive_[f]) return OpResult::DeadElement;
  k &= 1;
  const int a = F[f][k], b = F[f][k + 1], c = F[f][k + 2], d = F[f][(k + 3) & 3];
  if (boundary_[a] && boundary_[c]) return OpResult::BoundaryMerge;
  int keep = a, rem = c;
  if (boundary_[c]) std::swap(keep, rem);
  const Vec3 pos = boundary_[keep] ? P[keep] : Vec3(0.5 * (P[a] + P[c]));
  const size_t fm = fj_.size(), vm = vj_.size();
  SaveFace(f);
  SaveVert(a); SaveVert(b); SaveVert(c); SaveVert(d);
  KillFace(f);
  std::vector<int> moved = vf_[rem];
  for (int g : moved) {
    SaveFace(g);
    for (int j = 0; j < 4; ++j)
      if (F[g][j] == rem) F[g][j] = keep;
    vf_[keep].push_back(g);
  }
  vf_[rem].clear();
  vertAlive_[rem] = 0;
  --nVerts_;
  P[keep] = pos;
  std::vector<int> check{keep, b, d};
  for (int g : vf_[keep])
    for (int j = 0; j < 4; ++j) check.push_back(F[g][j]);
  OpResult r = LocalCheck(check, true);
  EndOp(fm, vm, r == OpResult::Ok);
  if (r == OpResult::Ok && survivor) *survivor = keep;
  return r;
}

bool QuadMesh::SwapEnergyDelta(int f, int k, int variant, int* delta) const {
  if (!faceAlive_[f]) return false;
  int g = AcrossEdge(f, k);
  if (g < 0) return false;
  const int u = F[f][k], v = F[f][(k + 1) & 3], a = F[f][(k + 2) & 3], b = F[f][(k + 3) & 3];
  const int kg = CornerOf(g, v);
  const int c = F[g][(kg + 2) & 3], d = F[g][(kg + 3) & 3];
  int verts[6] = {u, v, a, b, c, d};
  int dv[6] = {-1, -1, 0, 0, 0, 0};
  if (variant == 0) { dv[2] = 1; dv[4] = 1; } else { dv[3] = 1; dv[5] = 1; }
  int before = 0, after = 0;
  for (int i = 0; i < 6; ++i) {
    bool dup = false;
    for (int j = 0; j < i; ++j) dup |= verts[j] == verts[i];
    if (dup) return false;  // degenerate hexagon: refuse
    int val = Valence(verts[i]), reg = RegularValence(verts[i]);
    before += std::abs(val - reg);
    after += std::abs(val + dv[i] - reg);
  }
  *delta = after - before;
  return true;
}

int QuadMesh::ValenceEnergy(int f, int g) const {
  int verts[8], n = 0, e = 0;
  for (int h : {f, g})
    for (int j = 0; j < 4; ++j) {
      int v = F[h][j];
      if (std::find(verts, verts + n, v) == verts + n) {
        verts[n++] = v;
        e += std::abs(Valence(v) - RegularValence(v));
      }
    }
  return e;
}

OpResult QuadMesh::SwapEdge(int f, int k, int variant) {
  if (f < 0 || f >= int(F.size()) || !faceAlive_[f]) return OpResult::DeadElement;
  int g = AcrossEdge(f, k);
  if (g < 0) return OpResult::BoundaryEdge;
  const int u = F[f][k], v = F[f][(k + 1) & 3], a = F[f][(k + 2) & 3], b = F[f][(k + 3) & 3];
  const int kg = CornerOf(g, v);
  const int c = F[g][(kg + 2) & 3], d = F[g][(kg + 3) & 3];
  // hexagon (ccw): v a b u c d
  Quad nf, ng;
  if (variant == 0) { nf = {a, b, u, c}; ng = {c, d, v, a}; }
  else { nf = {b, u, c, d}; ng = {d, v, a, b}; }
  const size_t fm = fj_.size(), vm = vj_.size();
  int hex[6] = {u, v, a, b, c, d};
  SaveFace(f); SaveFace(g);
  for (int x : hex) SaveVert(x);
  for (int x : hex) { RemoveVF(x, f); RemoveVF(x, g); }
  F[f] = nf;
  F[g] = ng;
  for (int j = 0; j < 4; ++j) {
    auto& lf = vf_[nf[j]];
    if (std::find(lf.begin(), lf.end(), f) == lf.end()) lf.push_back(f);
    auto& lg = vf_[ng[j]];
    if (std::find(lg.begin(), lg.end(), g) == lg.end()) lg.push_back(g);
  }
  std::vector<int> check(hex, hex + 6);
  OpResult r = LocalCheck(check, false);
  EndOp(fm, vm, r == OpResult::Ok);
  return r;
}

OpResult QuadMesh::RemoveDoublet(int v) {
  if (v < 0 || v >= int(P.size()) || !vertAlive_[v]) return OpResult::DeadElement;
  if (boundary_[v] || vf_[v].size() != 2) return OpResult::NotDoublet;
  int f1 = vf_[v][0], f2 = vf_[v][1];
  int k1 = CornerOf(f1, v), k2 = CornerOf(f2, v);
  int a = F[f1][(k1 + 1) & 3], x = F[f1][(k1 + 2) & 3], b = F[f1][(k1 + 3) & 3];
  if (F[f2][(k2 + 1) & 3] != b || F[f2][(k2 + 3) & 3] != a) return OpResult::NonManifold;
  int y = F[f2][(k2 + 2) & 3];
  const size_t fm = fj_.size(), vm = vj_.size();
  SaveFace(f1); SaveFace(f2);
  SaveVert(v); SaveVert(a); SaveVert(b); SaveVert(x); SaveVert(y);
  KillFace(f2);
  RemoveVF(v, f1);
  F[f1] = {a, x, b, y};
  if (std::find(vf_[y].begin(), vf_[y].end(), f1) == vf_[y].end()) vf_[y].push_back(f1);
  vertAlive_[v] = 0;
  --nVerts_;
  OpResult r = LocalCheck({a, b, x, y}, true);
  EndOp(fm, vm, r == OpResult::Ok);
  return r;
}

OpResult QuadMesh::RemoveBoundaryCorner(int b, int* survivor, int keep) {
  if (b < 0 || b >= int(P.size()) || !vertAlive_[b]) return OpResult::DeadElement;
  if (!boundary_[b] || vf_[b].size() != 1) return OpResult::NotDoublet;
  const int f = vf_[b][0], k = CornerOf(f, b);
  int c = F[f][(k + 1) & 3], d = F[f][(k + 2) & 3], a = F[f][(k + 3) & 3];
  if (!boundary_[a] || !boundary_[c]) return OpResult::NonManifold;
  if (keep == 2) std::swap(a, c);  // survivor = c (index and position)
  const size_t fm = fj_.size(), vm = vj_.size();
  SaveFace(f);
  SaveVert(a); SaveVert(b); SaveVert(c); SaveVert(d);
  KillFace(f);
  vertAlive_[b] = 0;
  --nVerts_;
  std::vector<int> moved = vf_[c];
  for (int g : moved) {
    SaveFace(g);
    for (int j = 0; j < 4; ++j)
      if (F[g][j] == c) F[g][j] = a;
    vf_[a].push_back(g);
  }
  vf_[c].clear();
  vertAlive_[c] = 0;
  --nVerts_;
  if (keep == 0) P[a] = 0.5 * (P[a] + P[c]);
  std::vector<int> check{a, d};
  for (int g : vf_[a])
    for (int j = 0; j < 4; ++j) check.push_back(F[g][j]);
  OpResult r = LocalCheck(check, true);
  EndOp(fm, vm, r == OpResult::Ok);
  if (r == OpResult::Ok && survivor) *survivor = a;
  return r;
}

// ---------------------------------------------------------------------------- validity
QuadMesh::Invariants QuadMesh::ComputeInvariants() const {
  Invariants inv;
  const int nv = int(P.size());
  UnionFind dsu(nv);
  std::vector<std::uint64_t> he;
  for (size_t f = 0; f < F.size(); ++f) {
    if (!faceAlive_[f]) continue;
    for (int k = 0; k < 4; ++k) {
      dsu.Unite(F[f][k], F[f][(k + 1) & 3]);
      he.push_back((std::uint64_t(F[f][k]) << 32) | std::uint64_t(std::uint32_t(F[f][(k + 1) & 3])));
    }
  }
  std::sort(he.begin(), he.end());
  std::vector<int> root(nv, -1), compV, compE, compF, compLoops;
  auto compOf = [&](int v) {
    int r = dsu.Find(v);
    if (root[r] < 0) {
      root[r] = int(compV.size());
      compV.push_back(0); compE.push_back(0); compF.push_back(0); compLoops.push_back(0);
    }
    return root[r];
  };
  for (int v = 0; v < nv; ++v)
    if (vertAlive_[v]) ++compV[compOf(v)];
  for (size_t f = 0; f < F.size(); ++f)
    if (faceAlive_[f]) ++compF[compOf(F[f][0])];
  // edges: each half-edge counts 1/2 if twinned, 1 if boundary; boundary successor map
  std::vector<int> bnext(nv, -1);
  for (auto h : he) {
    int a = int(h >> 32), b = int(h & 0xffffffffu);
    std::uint64_t tw = (std::uint64_t(b) << 32) | std::uint64_t(std::uint32_t(a));
    bool twin = std::binary_search(he.begin(), he.end(), tw);
    if (!twin) { ++compE[compOf(a)]; bnext[b] = a; }  // boundary loop walked against the faces
    else if (a < b) ++compE[compOf(a)];
  }
  std::vector<char> seen(nv, 0);
  for (int v = 0; v < nv; ++v) {
    if (bnext[v] < 0 || seen[v]) continue;
    ++compLoops[compOf(v)];
    int x = v;
    while (x >= 0 && !seen[x]) { seen[x] = 1; x = bnext[x]; }
  }
  inv.components = int(compV.size());
  std::vector<std::pair<int, int>> pairs;
  for (size_t c = 0; c < compV.size(); ++c) {
    pairs.push_back({compV[c] - compE[c] + compF[c], compLoops[c]});
    inv.boundaryLoops += compLoops[c];
  }
  std::sort(pairs.begin(), pairs.end());
  for (auto& p : pairs) {
    inv.eulerPerComponent.push_back(p.first);
    inv.boundaryLoopsPerComponent.push_back(p.second);
  }
  return inv;
}

std::string QuadMesh::Check(const Invariants* ref) const {
  auto S = [](auto x) { return std::to_string(x); };
  int nf = 0, nv = 0;
  for (size_t f = 0; f < F.size(); ++f) {
    if (!faceAlive_[f]) continue;
    ++nf;
    const Quad& q = F[f];
    for (int k = 0; k < 4; ++k) {
      if (q[k] < 0 || q[k] >= int(P.size()) || !vertAlive_[q[k]])
        return "face " + S(f) + " references a dead/invalid vertex";
      for (int j = k + 1; j < 4; ++j)
        if (q[k] == q[j]) return "face " + S(f) + " is degenerate (repeated vertex " + S(q[k]) + ")";
      const auto& l = vf_[q[k]];
      if (std::find(l.begin(), l.end(), int(f)) == l.end())
        return "face " + S(f) + " missing from the face list of vertex " + S(q[k]);
    }
  }
  if (nf != nFaces_) return "face count mismatch";
  std::vector<std::uint64_t> he;
  for (size_t f = 0; f < F.size(); ++f)
    if (faceAlive_[f])
      for (int k = 0; k < 4; ++k)
        he.push_back((std::uint64_t(F[f][k]) << 32) | std::uint64_t(std::uint32_t(F[f][(k + 1) & 3])));
  std::sort(he.begin(), he.end());
  for (size_t i = 1; i < he.size(); ++i)
    if (he[i] == he[i - 1])
      return "half-edge " + S(int(he[i] >> 32)) + "->" + S(int(he[i] & 0xffffffffu)) +
             " occurs twice (non-manifold or inconsistently oriented edge)";
  std::vector<Wedge> w;
  for (size_t v = 0; v < P.size(); ++v) {
    if (!vertAlive_[v]) {
      if (!vf_[v].empty()) return "dead vertex " + S(v) + " has faces";
      continue;
    }
    ++nv;
    if (vf_[v].empty()) return "live vertex " + S(v) + " has no face";
    for (int f : vf_[v])
      if (!faceAlive_[f] || CornerOf(f, int(v)) < 0) return "stale face list at vertex " + S(v);
    bool open = false;
    if (!Fan(int(v), w, &open)) return "non-manifold vertex " + S(v);
    if (open != (boundary_[v] != 0)) return "boundary flag of vertex " + S(v) + " disagrees with its fan";
    if (!open && Valence(int(v)) < 3)
      return "interior vertex " + S(v) + " has valence " + S(Valence(int(v)));
  }
  if (nv != nVerts_) return "vertex count mismatch";
  if (ref) {
    Invariants cur = ComputeInvariants();
    if (cur.components != ref->components)
      return "component count changed: " + S(ref->components) + " -> " + S(cur.components);
    if (cur.eulerPerComponent != ref->eulerPerComponent) return "Euler characteristic changed";
    if (cur.boundaryLoopsPerComponent != ref->boundaryLoopsPerComponent || cur.boundaryLoops != ref->boundaryLoops)
      return "boundary loops changed: " + S(ref->boundaryLoops) + " -> " + S(cur.boundaryLoops);
  }
  return "";
}

QuadData QuadMesh::ToQuadData(std::vector<int>* vmapOut) const {
  QuadData q;
  std::vector<int> vmap(P.size(), -1);
  for (size_t v = 0; v < P.size(); ++v)
    if (vertAlive_[v]) { vmap[v] = int(q.V.size()); q.V.push_back(P[v]); }
  for (size_t f = 0; f < F.size(); ++f)
    if (faceAlive_[f]) q.F.push_back({vmap[F[f][0]], vmap[F[f][1]], vmap[F[f][2]], vmap[F[f][3]]});
  if (vmapOut) vmapOut->swap(vmap);
  return q;
}

std::vector<int> QuadMesh::ValenceHistogram(int* irregular) const {
  std::vector<int> h;
  int irr = 0;
  for (size_t v = 0; v < P.size(); ++v) {
    if (!vertAlive_[v]) continue;
    int val = Valence(int(v));
    if (val >= int(h.size())) h.resize(val + 1, 0);
    ++h[val];
    if (val != RegularValence(int(v))) ++irr;
  }
  if (irregular) *irregular = irr;
  return h;
}

}  // namespace quad
}  // namespace vcgext
