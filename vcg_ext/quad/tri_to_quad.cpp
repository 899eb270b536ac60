#include "vcg_ext/quad/tri_to_quad.h"

#include "vcg_ext/quad/quad_mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace vcgext {
namespace quad {

const char* ToString(TriToQuadPath p) {
  switch (p) {
    case TriToQuadPath::AlreadyQuads: return "already quads (used as is)";
    case TriToQuadPath::Pairing: return "triangle pairing";
    case TriToQuadPath::PairingBoundarySplit: return "triangle pairing after one boundary split (odd count)";
    case TriToQuadPath::SplitAll: return "fallback: split every face into quads";
  }
  return "?";
}

namespace {
using quad::OpResult;
using quad::QuadMesh;
std::uint64_t Key(int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }

// Twin of each triangle half-edge (t*3+k from corner k to k+1), -1 if none / non-manifold.
std::vector<int> TriTwins(const std::vector<Tri>& F) {
  std::unordered_map<std::uint64_t, int> he;
  he.reserve(F.size() * 4);
  std::vector<int> twin(F.size() * 3, -1);
  std::unordered_map<std::uint64_t, int> count;
  for (size_t t = 0; t < F.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      int a = F[t][k], b = F[t][(k + 1) % 3];
      he[Key(a, b)] = int(t * 3 + k);
      ++count[Key(std::min(a, b), std::max(a, b))];
    }
  for (size_t t = 0; t < F.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      int a = F[t][k], b = F[t][(k + 1) % 3];
      if (count[Key(std::min(a, b), std::max(a, b))] != 2) continue;
      auto it = he.find(Key(b, a));
      if (it != he.end()) twin[t * 3 + k] = it->second;
    }
  return twin;
}

double Angle(const Vec3& u, const Vec3& v) {
  double nu = u.norm(), nv = v.norm();
  if (!(nu > 0 && nv > 0)) return M_PI;
  return std::acos(std::clamp(u.dot(v) / (nu * nv), -1.0, 1.0));
}

// Quad from triangles t1 (edge a->b at corner k1) and its twin: (a, d, b, c).
Quad PairQuad(const std::vector<Tri>& F, int h1, int h2) {
  int t1 = h1 / 3, k1 = h1 % 3, t2 = h2 / 3, k2 = h2 % 3;
  int a = F[t1][k1], b = F[t1][(k1 + 1) % 3], c = F[t1][(k1 + 2) % 3];
  int d = F[t2][(k2 + 2) % 3];
  return {a, d, b, c};
}

double PairCost(const std::vector<Vec3>& V, const std::vector<Tri>& F, int h1, int h2) {
  Quad q = PairQuad(F, h1, h2);
  const Vec3 &a = V[q[0]], &d = V[q[1]], &b = V[q[2]], &c = V[q[3]];
  double angA = Angle(c - a, b - a) + Angle(b - a, d - a);
  double angB = Angle(a - b, c - b) + Angle(d - b, a - b);
  double angC = Angle(a - c, b - c), angD = Angle(a - d, b - d);
  Vec3 n1 = (b - a).cross(c - a), n2 = (d - a).cross(b - a);
  double pl = (n1.norm() > 0 && n2.norm() > 0) ? 1.0 - n1.normalized().dot(n2.normalized()) : 2.0;
  double h = M_PI / 2;
  return (std::abs(angA - h) + std::abs(angB - h) + std::abs(angC - h) + std::abs(angD - h)) / h + 2.0 * pl;
}
}  // namespace

QuadData SplitToQuads(const std::vector<Vec3>& Vin, const std::vector<Tri>& tris, const std::vector<Quad>& quads) {
  QuadData out;
  out.V = Vin;
  std::unordered_map<std::uint64_t, int> mid;
  auto M = [&](int a, int b) {
    auto k = Key(std::min(a, b), std::max(a, b));
    auto it = mid.find(k);
    if (it != mid.end()) return it->second;
    out.V.push_back(0.5 * (Vin[a] + Vin[b]));
    return mid[k] = int(out.V.size()) - 1;
  };
  for (const Quad& q : quads) {
    out.V.push_back(0.25 * (Vin[q[0]] + Vin[q[1]] + Vin[q[2]] + Vin[q[3]]));
    int C = int(out.V.size()) - 1;
    for (int k = 0; k < 4; ++k) out.F.push_back({q[k], M(q[k], q[(k + 1) & 3]), C, M(q[(k + 3) & 3], q[k])});
  }
  for (const Tri& t : tris) {
    out.V.push_back((Vin[t[0]] + Vin[t[1]] + Vin[t[2]]) / 3.0);
    int C = int(out.V.size()) - 1;
    for (int k = 0; k < 3; ++k) out.F.push_back({t[k], M(t[k], t[(k + 1) % 3]), C, M(t[(k + 2) % 3], t[k])});
  }
  return out;
}

namespace {

// A matching of triangles across shared edges. mate[t]: partner triangle, -1 unpaired, -2
// reserved for a boundary split; mateHe[t]: t's half-edge shared with its mate.
struct Pairing {
  std::vector<int> mate, mateHe;
  std::vector<int> splitAtBoundary;  ///< boundary half-edges of triangles split into two halves
  int greedy = 0, augmented = 0;
};

// 1. greedy pairing, best quad first; `forbidden` half-edges are never paired across.
void GreedyPairs(const std::vector<Vec3>& V, const std::vector<Tri>& F, const std::vector<int>& twin,
                 const std::vector<char>& forbidden, Pairing& pr) {
  struct Cand { double cost; int h1, h2; };
  std::vector<Cand> cand;
  cand.reserve(F.size() * 3 / 2);
  for (int h = 0; h < int(twin.size()); ++h)
    if (twin[h] > h && !forbidden[h]) cand.push_back({PairCost(V, F, h, twin[h]), h, twin[h]});
  std::sort(cand.begin(), cand.end(), [](const Cand& x, const Cand& y) { return x.cost < y.cost; });
  for (const Cand& c : cand) {
    int t1 = c.h1 / 3, t2 = c.h2 / 3;
    if (t1 == t2 || pr.mate[t1] >= 0 || pr.mate[t2] >= 0) continue;
    pr.mate[t1] = t2; pr.mate[t2] = t1;
    pr.mateHe[t1] = c.h1; pr.mateHe[t2] = c.h2;
    ++pr.greedy;
  }
}

// Breadth-first search over alternating paths from an unpaired root (bounded to 20000 nodes).
// `accept(x)` ends the search at an even node x (returns the half-edge to record, or -1 to go
// on); `free(y)` says that y, reached across an edge, ends an augmenting path. Returns the end.
struct AltSearch {
  std::vector<int> prevEven, via, viaHe, seen;
  int stamp = 0;
  explicit AltSearch(int nt) : prevEven(nt, -1), via(nt, -1), viaHe(nt, -1), seen(nt, 0) {}
  // Marks y (reached from even node x across half-edge h) and its mate z, the next even node.
  void Reach(int x, int y, int z, int h, std::vector<int>& queue) {
    seen[y] = stamp;
    seen[z] = stamp;
    prevEven[z] = x;
    via[z] = y;
    viaHe[z] = h;  // half-edge of x towards y
    queue.push_back(z);
  }
  // Flips the path root .. x so that x's old partner chain moves one step towards the root.
  void Flip(int root, int x, const std::vector<int>& twin, Pairing& pr) const {
    while (x != root) {
      int y = via[x], px = prevEven[x], h = viaHe[x];
      pr.mate[px] = y; pr.mate[y] = px;
      pr.mateHe[px] = h; pr.mateHe[y] = twin[h];
      x = px;
    }
  }
};

// 2. augmenting alternating paths pair the triangles the greedy pass left.
void AugmentPairs(const std::vector<int>& twin, const std::vector<char>& forbidden, int passes, Pairing& pr,
                  AltSearch& s) {
  const int nt = int(pr.mate.size());
  for (int pass = 0; pass < passes; ++pass) {
    int gained = 0, left = 0;
    for (int root = 0; root < nt; ++root) {
      if (pr.mate[root] != -1) continue;
      ++left;
      ++s.stamp;
      std::vector<int> queue{root};
      s.seen[root] = s.stamp;
      int foundX = -1, foundY = -1, foundH = -1;
      for (size_t qi = 0; qi < queue.size() && foundX < 0 && queue.size() < 20000; ++qi) {
        int x = queue[qi];
        for (int k = 0; k < 3; ++k) {
          int h = x * 3 + k, th = twin[h];
          if (th < 0 || forbidden[h]) continue;
          int y = th / 3;
          if (y == x || s.seen[y] == s.stamp || pr.mate[y] == -2) continue;
          if (pr.mate[y] == -1) { foundX = x; foundY = y; foundH = h; break; }
          int z = pr.mate[y];
          if (s.seen[z] == s.stamp) continue;
          s.Reach(x, y, z, h, queue);
        }
      }
      if (foundX < 0) continue;
      s.Flip(root, foundX, twin, pr);
      pr.mate[foundX] = foundY; pr.mate[foundY] = foundX;
      pr.mateHe[foundX] = foundH; pr.mateHe[foundY] = twin[foundH];
      ++gained;
      ++pr.augmented;
    }
    if (gained == 0 || left == gained) break;
  }
}

// 2b. Edmonds' blossom search for the triangles the plain alternating BFS leaves: the dual graph
// of a triangle mesh has odd cycles, around which the plain search misses augmenting paths (on
// a closed mesh a perfect matching always exists: Petersen's theorem). Work arrays are reset
// only where a search touched them, so each search costs what it explores (bounded).
class BlossomSearch {
 public:
  BlossomSearch(const std::vector<int>& twin, const std::vector<char>& forbidden, std::vector<int>& match)
      : twin_(twin), forbidden_(forbidden), match_(match), parent_(match.size()), label_(match.size()),
        p_(match.size()), used_(match.size(), 0), mark_(match.size(), 0), touched_(match.size(), 0) {}
  /// Finds an augmenting path from the unpaired `root` and flips it; false if none within
  /// `maxTouched` explored triangles.
  bool Augment(int root, size_t maxTouched) {
    int end = FindPath(root, maxTouched);
    for (int v : list_) touched_[v] = 0;
    list_.clear();
    if (end < 0) return false;
    for (int v = end; v != -1;) {
      int pv = p_[v], next = match_[pv];
      match_[v] = pv;
      match_[pv] = v;
      v = next;
    }
    return true;
  }

 private:
  int Neighbour(int v, int k) const {
    const int h = v * 3 + k;
    return twin_[h] < 0 || forbidden_[h] ? -1 : twin_[h] / 3;
  }
  void Touch(int v) {
    if (touched_[v]) return;
    touched_[v] = 1;
    list_.push_back(v);
    parent_[v] = v;
    label_[v] = v;
    p_[v] = -1;
    used_[v] = 0;
  }
  // Blossom bases as a union-find: the base of v is the label of its set's root, so a
  // contraction costs the length of its cycle, not the size of the search.
  int Find(int v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  int Base(int v) { return label_[Find(v)]; }
  int Lca(int a, int b) {
    ++stamp_;
    for (;;) {
      a = Base(a);
      mark_[a] = stamp_;
      if (match_[a] == -1) break;
      a = p_[match_[a]];
    }
    for (;;) {
      b = Base(b);
      if (mark_[b] == stamp_) return b;
      b = p_[match_[b]];
    }
  }
  // Walks from v up to the blossom base b, redirecting parents; collects the bases to merge and
  // the inner vertices, which become outer.
  void MarkPath(int v, int b, int child, std::vector<int>& bases, std::vector<int>& q) {
    while (Base(v) != b) {
      bases.push_back(Base(v));
      bases.push_back(Base(match_[v]));
      if (!used_[match_[v]]) { used_[match_[v]] = 1; q.push_back(match_[v]); }
      p_[v] = child;
      child = match_[v];
      v = p_[match_[v]];
    }
  }
  int FindPath(int root, size_t maxTouched) {
    Touch(root);
    used_[root] = 1;
    std::vector<int> q{root}, bases;
    for (size_t head = 0; head < q.size() && list_.size() < maxTouched; ++head) {
      const int v = q[head];
      for (int k = 0; k < 3; ++k) {
        const int to = Neighbour(v, k);
        if (to < 0) continue;
        Touch(to);
        if (Base(v) == Base(to) || match_[v] == to) continue;
        if (match_[to] != -1) Touch(match_[to]);
        if (to == root || (match_[to] != -1 && p_[match_[to]] != -1)) {
          const int cur = Lca(v, to);  // contracts the odd cycle into a blossom with base cur
          bases.clear();
          MarkPath(v, cur, to, bases, q);
          MarkPath(to, cur, v, bases, q);
          for (int b : bases) parent_[Find(b)] = Find(cur);
          label_[Find(cur)] = cur;
        } else if (p_[to] == -1) {
          p_[to] = v;
          if (match_[to] == -1) return to;
          used_[match_[to]] = 1;
          q.push_back(match_[to]);
        }
      }
    }
    return -1;
  }
  const std::vector<int>& twin_;
  const std::vector<char>& forbidden_;
  std::vector<int>& match_;
  std::vector<int> parent_, label_, p_;
  std::vector<char> used_;
  std::vector<unsigned> mark_;
  std::vector<char> touched_;
  std::vector<int> list_;
  unsigned stamp_ = 0;
};

void BlossomPairs(const std::vector<int>& twin, const std::vector<char>& forbidden, Pairing& pr) {
  const int nt = int(pr.mate.size());
  BlossomSearch bs(twin, forbidden, pr.mate);
  bool any = false;
  for (int root = 0; root < nt; ++root)
    if (pr.mate[root] == -1 && bs.Augment(root, size_t(-1))) { ++pr.augmented; any = true; }
  if (!any) return;
  for (int t = 0; t < nt; ++t) {  // the shared half-edge of every (possibly new) pair
    if (pr.mate[t] < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const int h = t * 3 + k;
      if (twin[h] >= 0 && !forbidden[h] && twin[h] / 3 == pr.mate[t]) { pr.mateHe[t] = h; break; }
    }
  }
}

// 3. leftovers (odd counts, or blocked pairings on open meshes): shift the free slot along an
// alternating path to a triangle with a boundary edge, which is split at the edge midpoint into
// two paired halves (a quad with a flat corner at a new boundary vertex of valence 2).
void ReserveBoundarySplits(const std::vector<int>& twin, const std::vector<char>& forbidden, Pairing& pr,
                           AltSearch& s) {
  const int nt = int(pr.mate.size());
  for (int root = 0; root < nt; ++root) {
    if (pr.mate[root] != -1) continue;  // paired, or already reserved for a split (-2)
    ++s.stamp;
    std::vector<int> queue{root};
    s.seen[root] = s.stamp;
    int z = -1, zh = -1;
    for (size_t qi = 0; qi < queue.size() && z < 0 && queue.size() < 20000; ++qi) {
      int x = queue[qi];
      for (int k = 0; k < 3; ++k)
        if (twin[x * 3 + k] < 0) { z = x; zh = x * 3 + k; break; }
      if (z >= 0) break;
      for (int k = 0; k < 3; ++k) {
        int h = x * 3 + k, th = twin[h];
        if (th < 0 || forbidden[h]) continue;
        int y = th / 3;
        if (s.seen[y] == s.stamp || pr.mate[y] < 0) continue;
        int zz = pr.mate[y];
        if (s.seen[zz] == s.stamp) continue;
        s.Reach(x, y, zz, h, queue);
      }
    }
    if (z < 0) continue;
    s.Flip(root, z, twin, pr);
    pr.mate[z] = -2;
    pr.splitAtBoundary.push_back(zh);
  }
}

Pairing PairTriangles(const std::vector<Vec3>& V, const std::vector<Tri>& F, const std::vector<int>& twin,
                      const std::vector<char>& forbidden, const TriToQuadParams& p) {
  const int nt = int(F.size());
  Pairing pr;
  pr.mate.assign(nt, -1);
  pr.mateHe.assign(nt, -1);
  AltSearch s(nt);
  GreedyPairs(V, F, twin, forbidden, pr);
  AugmentPairs(twin, forbidden, p.maxAugmentPasses, pr, s);
  if (p.maxAugmentPasses > 0) BlossomPairs(twin, forbidden, pr);
  ReserveBoundarySplits(twin, forbidden, pr, s);
  return pr;
}

// Interior vertices left in only two quads (doublets) are merged away where that is valid.
int RemovePairingDoublets(QuadMesh& qm) {
  int total = 0;
  for (int pass = 0; pass < 4; ++pass) {
    int removed = 0;
    for (int v = 0; v < qm.NumVertexSlots(); ++v)
      if (qm.VertAlive(v) && !qm.IsBoundary(v) && qm.Valence(v) == 2 && qm.RemoveDoublet(v) == OpResult::Ok)
        ++removed;
    total += removed;
    if (!removed) break;
  }
  return total;
}

// Vertices where a quad mesh is invalid: interior valence < 3, a fan that is not one disk, or an
// end of a half-edge that occurs twice.
std::vector<int> InvalidVertices(const QuadMesh& qm) {
  std::vector<int> bad;
  std::vector<Wedge> w;
  for (int v = 0; v < qm.NumVertexSlots(); ++v) {
    if (!qm.VertAlive(v) || qm.VF(v).empty()) continue;
    bool open = false;
    if (!qm.Fan(v, w, &open) || (!open && qm.Valence(v) < 3)) bad.push_back(v);
  }
  std::vector<std::pair<std::uint64_t, int>> he;
  for (int f = 0; f < qm.NumFaceSlots(); ++f)
    if (qm.FaceAlive(f))
      for (int k = 0; k < 4; ++k) he.push_back({Key(qm.F[f][k], qm.F[f][(k + 1) & 3]), f});
  std::sort(he.begin(), he.end());
  for (size_t i = 1; i < he.size(); ++i)
    if (he[i].first == he[i - 1].first) {
      bad.push_back(int(he[i].first >> 32));
      bad.push_back(int(he[i].first & 0xffffffffu));
    }
  return bad;
}

// The topology the quads must keep: the same as splitting every triangle into three quads.
QuadMesh::Invariants TriangleInvariants(const TriData& m) {
  QuadData all = SplitToQuads(m.V, m.F, {});
  return QuadMesh(all.V, all.F).ComputeInvariants();
}

// The quads of pairing `pr` (a pair's quad; a boundary split's two halves, its midpoint appended
// to V) and the number of triangles left alone.
int QuadsOfPairing(const std::vector<Tri>& F, const Pairing& pr, std::vector<Vec3>& V, std::vector<Quad>& quads) {
  int lone = 0;
  for (int t = 0; t < int(F.size()); ++t) {
    if (pr.mate[t] == -1) ++lone;
    else if (pr.mate[t] >= 0 && t < pr.mate[t]) quads.push_back(PairQuad(F, pr.mateHe[t], pr.mateHe[pr.mate[t]]));
  }
  for (int h : pr.splitAtBoundary) {
    const Tri& t = F[h / 3];
    int a = t[h % 3], b = t[(h % 3 + 1) % 3], c = t[(h % 3 + 2) % 3];
    V.push_back(0.5 * (V[a] + V[b]));
    quads.push_back({a, int(V.size()) - 1, b, c});  // halves (a, mm, c) and (mm, b, c)
  }
  return lone;
}

// Forbids pairing across every edge at the vertices `bad` (both half-edges); split vertices
// (beyond the input's) are skipped: their triangle's corners are marked too. Returns how many
// vertices were marked.
int ForbidEdgesAt(const std::vector<int>& bad, const TriData& m, const std::vector<int>& twin, Adjacency& vf,
                  std::vector<char>& forbidden) {
  const std::vector<Tri>& F = m.F;
  if (vf.offs.empty()) vf = VertexFaceAdjacency(F, int(m.V.size()));
  int marked = 0;
  for (int v : bad) {
    if (v >= int(m.V.size())) continue;
    ++marked;
    for (const int* it = vf.Begin(v); it != vf.End(v); ++it)
      for (int k = 0; k < 3; ++k) {
        const Tri& t = F[*it];
        if (t[k] != v && t[(k + 1) % 3] != v) continue;
        const int h = *it * 3 + k;
        forbidden[h] = 1;
        if (twin[h] >= 0) forbidden[twin[h]] = 1;
      }
  }
  return marked;
}

// Fallback: every triangle into three quads (edge midpoints + centre). On a manifold,
// consistently oriented mesh this is always valid: input vertices keep their triangle
// valence, midpoints get 4 (3 on the boundary), centres 3.
void SplitAll(const TriData& m, TriToQuadResult& res) {
  res.path = TriToQuadPath::SplitAll;
  res.quads = SplitToQuads(m.V, m.F, {});
  res.addedVertices = int(res.quads.V.size() - m.V.size());
  res.boundarySplits = 0;
  res.doubletsRemoved = 0;
}
}  // namespace

TriToQuadResult TriToQuad(const TriData& m, const TriToQuadParams& p) {
  TriToQuadResult res;
  const std::vector<Tri>& F = m.F;
  if (F.empty()) { res.error = "no triangles"; return res; }
  std::vector<int> twin = TriTwins(F);
  const QuadMesh::Invariants ref = TriangleInvariants(m);
  // Pairing can leave a vertex in two quads that doublet removal cannot merge (the merge would
  // repeat an edge), or make two quads share two edges. Such vertices are repaired by pairing
  // again with every edge at them forbidden: a vertex whose triangles pair across none of its
  // edges keeps its triangle valence (>= 3 inside a manifold mesh).
  std::vector<char> forbidden(F.size() * 3, 0);
  Adjacency vf;
  for (int attempt = 0; attempt <= p.maxRepairRounds; ++attempt) {
    Pairing pr = PairTriangles(m.V, F, twin, forbidden, p);
    res.greedyPairs = pr.greedy;
    res.augmentedPairs = pr.augmented;
    std::vector<Vec3> V = m.V;
    std::vector<Quad> quads;
    res.unpairedTriangles = QuadsOfPairing(F, pr, V, quads);
    if (res.unpairedTriangles > 0) break;  // only blocked matchings on open meshes: no repair round helps
    QuadMesh qm(V, quads);
    res.doubletsRemoved = RemovePairingDoublets(qm);
    std::vector<int> bad = InvalidVertices(qm);
    if (bad.empty() && qm.Check(&ref).empty()) {
      res.path = pr.splitAtBoundary.empty() ? TriToQuadPath::Pairing : TriToQuadPath::PairingBoundarySplit;
      res.boundarySplits = int(pr.splitAtBoundary.size());
      res.addedVertices = res.boundarySplits;
      res.quads.V = std::move(V);
      for (int f = 0; f < qm.NumFaceSlots(); ++f)
        if (qm.FaceAlive(f)) res.quads.F.push_back(qm.F[f]);
      return res;
    }
    if (bad.empty()) break;  // invalid for another reason (topology changed): fall back
    res.repairedVertices += ForbidEdgesAt(bad, m, twin, vf, forbidden);
    ++res.repairRounds;
  }
  if (!p.allowSplitFallback) {
    res.error = res.unpairedTriangles > 0 ? std::to_string(res.unpairedTriangles) + " triangles could not be paired"
                                          : "triangle pairing gave no valid quad mesh";
    return res;
  }
  SplitAll(m, res);
  return res;
}

}  // namespace quad
}  // namespace vcgext
