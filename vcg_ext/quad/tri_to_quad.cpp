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

TriToQuadResult TriToQuad(const TriData& m, const TriToQuadParams& p) {
  TriToQuadResult res;
  std::vector<Vec3> V = m.V;
  std::vector<Tri> F = m.F;
  if (F.empty()) { res.error = "no triangles"; return res; }
  std::vector<int> twin = TriTwins(F);
  const int nt = int(F.size());
  std::vector<int> mate(nt, -1), mateHe(nt, -1);  // mateHe: half-edge of t shared with its mate
  // 1. greedy
  struct Cand { double cost; int h1, h2; };
  std::vector<Cand> cand;
  cand.reserve(F.size() * 3 / 2);
  for (int h = 0; h < nt * 3; ++h)
    if (twin[h] > h) cand.push_back({PairCost(V, F, h, twin[h]), h, twin[h]});
  std::sort(cand.begin(), cand.end(), [](const Cand& x, const Cand& y) { return x.cost < y.cost; });
  for (const Cand& c : cand) {
    int t1 = c.h1 / 3, t2 = c.h2 / 3;
    if (t1 == t2 || mate[t1] >= 0 || mate[t2] >= 0) continue;
    mate[t1] = t2; mate[t2] = t1;
    mateHe[t1] = c.h1; mateHe[t2] = c.h2;
    ++res.greedyPairs;
  }
  // 2. augmenting paths (BFS over alternating paths, bounded)
  std::vector<Quad> splitQuads;
  std::vector<int> prevEven(nt, -1), via(nt, -1), viaHe(nt, -1), seen(nt, 0);
  int stampv = 0;
  for (int pass = 0; pass < p.maxAugmentPasses; ++pass) {
    int gained = 0, left = 0;
    for (int root = 0; root < nt; ++root) {
      if (mate[root] >= 0) continue;
      ++left;
      ++stampv;
      std::vector<int> queue{root};
      seen[root] = stampv;
      int foundX = -1, foundY = -1, foundH = -1;
      for (size_t qi = 0; qi < queue.size() && foundX < 0 && queue.size() < 20000; ++qi) {
        int x = queue[qi];
        for (int k = 0; k < 3; ++k) {
          int h = x * 3 + k, th = twin[h];
          if (th < 0) continue;
          int y = th / 3;
          if (y == x || seen[y] == stampv) continue;
          if (mate[y] < 0) { foundX = x; foundY = y; foundH = h; break; }
          int z = mate[y];
          if (seen[z] == stampv) continue;
          seen[y] = stampv;
          seen[z] = stampv;
          prevEven[z] = x;
          via[z] = y;
          viaHe[z] = h;  // half-edge of x towards y
          queue.push_back(z);
        }
      }
      if (foundX < 0) continue;
      int x = foundX, y = foundY, hx = foundH;
      while (true) {
        bool isRoot = x == root;
        int px = isRoot ? -1 : prevEven[x], vy = isRoot ? -1 : via[x], vh = isRoot ? -1 : viaHe[x];
        mate[x] = y; mate[y] = x;
        mateHe[x] = hx; mateHe[y] = twin[hx];
        if (isRoot) break;
        x = px; y = vy; hx = vh;
      }
      ++gained;
      ++res.augmentedPairs;
    }
    if (gained == 0 || left == gained) break;
  }
  // 3. leftovers (odd counts, or blocked pairings on open meshes): shift the free slot along an
  // alternating path to a triangle with a boundary edge and split that one at the edge midpoint
  // into two paired halves (a quad with a flat corner at a new boundary vertex of valence 2).
  std::vector<int> splitAtBoundary;  // half-edges (boundary) of triangles to split
  for (int root = 0; root < nt; ++root) {
    if (mate[root] >= 0) continue;
    ++stampv;
    std::vector<int> queue{root};
    seen[root] = stampv;
    int z = -1, zh = -1;
    for (size_t qi = 0; qi < queue.size() && z < 0 && queue.size() < 20000; ++qi) {
      int x = queue[qi];
      for (int k = 0; k < 3; ++k)
        if (twin[x * 3 + k] < 0) { z = x; zh = x * 3 + k; break; }
      if (z >= 0) break;
      for (int k = 0; k < 3; ++k) {
        int h = x * 3 + k, th = twin[h];
        if (th < 0) continue;
        int y = th / 3;
        if (seen[y] == stampv || mate[y] < 0) continue;
        int zz = mate[y];
        if (seen[zz] == stampv) continue;
        seen[y] = stampv;
        seen[zz] = stampv;
        prevEven[zz] = x;
        via[zz] = y;
        viaHe[zz] = h;
        queue.push_back(zz);
      }
    }
    if (z < 0) continue;
    int x = z;
    mate[z] = -2;  // reserved for a boundary split
    while (x != root) {
      int y = via[x], px = prevEven[x], h = viaHe[x];
      mate[px] = y; mate[y] = px;
      mateHe[px] = h; mateHe[y] = twin[h];
      x = px;
    }
    splitAtBoundary.push_back(zh);
  }
  for (int h : splitAtBoundary) {
    int t = h / 3, k = h % 3;
    int a = F[t][k], b = F[t][(k + 1) % 3], c = F[t][(k + 2) % 3];
    V.push_back(0.5 * (V[a] + V[b]));
    int mm = int(V.size()) - 1;
    // halves (a, mm, c) and (mm, b, c) paired across mm-c: quad (a, mm, b, c)
    splitQuads.push_back({a, mm, b, c});
    res.path = TriToQuadPath::PairingBoundarySplit;
    ++res.addedVertices;
    ++res.boundarySplits;
  }
  std::vector<Quad> quads;
  std::vector<Tri> lone;
  for (int t = 0; t < nt; ++t) {
    if (mate[t] == -2) continue;  // split at the boundary above
    if (mate[t] < 0) { lone.push_back(F[t]); continue; }
    if (t < mate[t]) quads.push_back(PairQuad(F, mateHe[t], mateHe[mate[t]]));
  }
  quads.insert(quads.end(), splitQuads.begin(), splitQuads.end());
  res.unpairedTriangles = int(lone.size());
  if (lone.empty()) {
    // pairing can leave interior vertices in only two quads (doublets): merge them
    QuadMesh qm(V, quads);
    for (int pass = 0; pass < 4; ++pass) {
      int removed = 0;
      for (int v = 0; v < qm.NumVertexSlots(); ++v)
        if (qm.VertAlive(v) && !qm.IsBoundary(v) && qm.Valence(v) == 2 && qm.RemoveDoublet(v) == OpResult::Ok) ++removed;
      res.doubletsRemoved += removed;
      if (!removed) break;
    }
    res.quads.V = std::move(V);
    for (int f = 0; f < qm.NumFaceSlots(); ++f)
      if (qm.FaceAlive(f)) res.quads.F.push_back(qm.F[f]);
    return res;
  }
  if (!p.allowSplitFallback) {
    res.error = std::to_string(lone.size()) + " triangles could not be paired";
    return res;
  }
  res.path = TriToQuadPath::SplitAll;
  res.quads = SplitToQuads(V, lone, quads);
  res.addedVertices = int(res.quads.V.size() - m.V.size());
  return res;
}

}  // namespace quad
}  // namespace vcgext
