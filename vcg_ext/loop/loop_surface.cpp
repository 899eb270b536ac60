/// \file loop_surface.cpp
/// Loop surface kernel: per face, a tree of regular box-spline patches (loop_patch.cpp, §3.1) and
/// local subdivision of irregular triangles (loop_local_subdivision.cpp, §3.2) down to the
/// self-similar rings, evaluated with the nudge (§3.2, Fig. 8); hard edges / vertices by the 1-D
/// spline rules (§2.4). The internals' shared types are in loop_net.h.
#include "vcg_ext/loop/loop_surface.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#ifdef __linux__
#include <sys/mman.h>
#endif

#include "vcg_ext/core/memory.h"
#include "vcg_ext/loop/loop_net.h"

namespace vcgext {

using namespace loop_internal;

namespace {

/// Child selection and affine parameter map (v', w') = A (v, w) + b (see the file comment).
inline int ChildOf(double v, double w) {
  if (v + w <= 0.5) return 0;
  if (v >= 0.5) return 1;
  if (w >= 0.5) return 2;
  return 3;
}
const double kA[4][2][2] = {{{2, 0}, {0, 2}}, {{0, 2}, {-2, -2}}, {{-2, -2}, {2, 0}}, {{-2, 0}, {0, -2}}};
const double kB[4][2] = {{0, 0}, {0, 2}, {2, 0}, {1, 1}};

inline void ClampParam(double& v, double& w) {
  if (v < 0) v = 0;
  if (w < 0) w = 0;
  double s = v + w;
  if (s > 1) { v /= s; w /= s; }
}

struct Node {
  int child[4] = {-1, -1, -1, -1};
  int patch = -1;
  int net = -1;
};

struct TriCache {
  std::vector<Node> nodes;
  std::vector<Patch> patches;
  std::vector<LNet> nets;
};

}  // namespace

// Flat evaluation tree (all faces in one arena each): a "code" is a node (>= 0: index into
// `nodes`, 4 child codes each), a tile (-1 - index into `tiles`, a box-spline patch) or a net to be
// subdivided on the fly (kNetBase + index into `nets`). Per face, its nodes and tiles are
// contiguous and in breadth-first order, so the shallow tiles that random queries hit most
// (depth 1: 60%, depth 2: 30% of the points of an irregular face) share a few cache lines/pages.
constexpr int32_t kNetBase = INT32_MIN;
constexpr int32_t kTileMin = -(1 << 30);  // codes in [kTileMin, -1] are tiles
inline bool IsTile(int32_t c) { return c < 0 && c >= kTileMin; }

struct LoopSurface::Impl {
  std::vector<int32_t> root;  // per face: root code
  std::vector<std::array<int32_t, 4>> nodes;
  std::vector<Patch> tiles;
  std::vector<LNet> nets;
  std::vector<int> netRing;      // per net: index into rings, -1 if not self-similar (slow path)
  std::vector<Ring> rings;
  std::vector<TriCache> cache;  // construction only (irregular faces, DFS), freed after flattening
  std::vector<std::vector<int>> hardNb;  // per vertex: hard-edge neighbours
  Adjacency vv;
  int maxDepth = 25;
  double diag = 0;
  /// Exact limit masks (vertex, weight) of darts: smooth vertices with one hard edge. Their
  /// 1-ring subdivision matrix has a midpoint row for the hard edge, so the smooth Loop limit
  /// mask (which OpenSubdiv's Sdc also uses for darts) is only an approximation.
  std::vector<std::pair<int, std::vector<std::pair<int, double>>>> dartMasks;  // sorted by vertex
  const std::vector<std::pair<int, double>>* DartMask(int i) const {
    auto it = std::lower_bound(dartMasks.begin(), dartMasks.end(), i,
                               [](const std::pair<int, std::vector<std::pair<int, double>>>& a, int b) { return a.first < b; });
    return it != dartMasks.end() && it->first == i ? &it->second : nullptr;
  }

  void BuildPatches(const TriData& net, const std::vector<LoopVertexType>& vtype,
                    const std::vector<std::array<unsigned char, 3>>& hard, const Adjacency& vf, int cacheDepth,
                    std::vector<char>& isReg, std::vector<Patch>& tmpPatch);
  int Flatten(int nF, const std::vector<char>& isReg, const std::vector<Patch>& tmpPatch);
  int BuildNode(TriCache& tc, const LNet& n, int depth, int cacheDepth) {
    int id = int(tc.nodes.size());
    tc.nodes.emplace_back();
    Vec3 X[12];
    if (Gather(n, X)) {
      tc.nodes[id].patch = int(tc.patches.size());
      tc.patches.push_back(MakePatch(X));
      return id;
    }
    if (depth >= cacheDepth) {
      tc.nodes[id].net = int(tc.nets.size());
      tc.nets.push_back(n);
      return id;
    }
    for (int c = 0; c < 4; ++c) {
      int ch = BuildNode(tc, Subdivide(n, c), depth + 1, cacheDepth);
      tc.nodes[id].child[c] = ch;
    }
    return id;
  }
};

namespace {

/// Applies the accumulated chain rule: derivatives w.r.t. the original (v,w) from those w.r.t.
/// the leaf parameters, J = d(leaf)/d(orig).
inline void ApplyJacobian(const double J[2][2], LoopEval& e, int order) {
  if (order < 1) return;
  Vec3 dv = J[0][0] * e.Dv + J[1][0] * e.Dw;
  Vec3 dw = J[0][1] * e.Dv + J[1][1] * e.Dw;
  e.Dv = dv;
  e.Dw = dw;
  if (order < 2) return;
  // H = J^T H' J
  Vec3 h00 = e.Dvv, h01 = e.Dvw, h11 = e.Dww;
  auto comb = [&](int a, int b) {
    return Vec3(J[0][a] * J[0][b] * h00 + (J[0][a] * J[1][b] + J[1][a] * J[0][b]) * h01 + J[1][a] * J[1][b] * h11);
  };
  e.Dvv = comb(0, 0);
  e.Dvw = comb(0, 1);
  e.Dww = comb(1, 1);
}

inline void StepJ(double J[2][2], int c) {
  double N[2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) N[i][j] = kA[c][i][0] * J[0][j] + kA[c][i][1] * J[1][j];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) J[i][j] = N[i][j];
}

}  // namespace

LoopCurvature CurvatureFromDerivatives(const LoopEval& e) {
  LoopCurvature k;
  double E = e.Dv.dot(e.Dv), F = e.Dv.dot(e.Dw), G = e.Dw.dot(e.Dw);
  double det = E * G - F * F;
  if (!(det > 0) || e.N.squaredNorm() == 0) return k;
  double L = -e.Dvv.dot(e.N), M = -e.Dvw.dot(e.N), N = -e.Dww.dot(e.N);
  double H = (E * N - 2 * F * M + G * L) / (2 * det);
  double K = (L * N - M * M) / det;
  double disc = std::sqrt(std::max(0.0, H * H - K));
  k.k1 = H + disc;
  k.k2 = H - disc;
  auto dir = [&](double kk) {
    // (II - k I) x = 0
    double a0 = M - kk * F, a1 = -(L - kk * E);
    double b0 = N - kk * G, b1 = -(M - kk * F);
    double x0, x1;
    if (a0 * a0 + a1 * a1 >= b0 * b0 + b1 * b1) { x0 = a0; x1 = a1; } else { x0 = b0; x1 = b1; }
    if (x0 * x0 + x1 * x1 < 1e-300) { x0 = 1; x1 = 0; }
    Vec3 d = x0 * e.Dv + x1 * e.Dw;
    double l = d.norm();
    return l > 0 ? Vec3(d / l) : d;
  };
  k.d1 = dir(k.k1);
  k.d2 = e.N.cross(k.d1);
  if (disc < 1e-14 * (std::abs(H) + 1e-300)) {  // umbilic: any orthonormal pair
    k.d1 = e.Dv.normalized();
    k.d2 = e.N.cross(k.d1);
  }
  return k;
}

LoopSurface::LoopSurface() : impl_(new Impl) {}
LoopSurface::~LoopSurface() = default;
LoopSurface::LoopSurface(LoopSurface&&) noexcept = default;
LoopSurface& LoopSurface::operator=(LoopSurface&&) noexcept = default;

namespace {

// What makes a control net unusable (empty: nothing): no faces, non-finite coordinates, bad or
// repeated indices, a vertex of more than maxValence triangles.
std::string CheckNet(const TriData& net, const LoopSurfaceParams& p) {
  const int nV = int(net.V.size()), nF = int(net.F.size());
  if (nV == 0 || nF == 0) { return "the control net is empty (" + std::to_string(nV) + " vertices, " + std::to_string(nF) + " faces)"; }
  {
    int bad = 0, first = -1;
    for (int i = 0; i < nV; ++i)
      if (!net.V[i].allFinite()) { if (first < 0) first = i; ++bad; }
    if (bad) { return std::to_string(bad) + " vertices have NaN or infinite coordinates (first: vertex " + std::to_string(first) + ")"; }
  }
  for (int f = 0; f < nF; ++f) {
    const Tri& t = net.F[f];
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || t[k] >= nV) { return "face " + std::to_string(f) + " has an out-of-range vertex index " + std::to_string(t[k]); }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) { return "face " + std::to_string(f) + " repeats a vertex"; }
  }
  if (p.maxValence > 0) {
    std::vector<int> valence(nV, 0);
    for (const auto& t : net.F)
      for (int v : t) ++valence[v];
    const auto it = std::max_element(valence.begin(), valence.end());
    if (*it > p.maxValence) {
      return "vertex " + std::to_string(it - valence.begin()) + " is in " + std::to_string(*it) +
               " triangles (at most " + std::to_string(p.maxValence) +
               " are supported: the Loop evaluation around such a vertex takes minutes); remesh the layer first "
               "(Filters > Remeshing, Simplification and Reconstruction > Remeshing: Isotropic Explicit Remeshing)";
    }
  }
  return {};
}

// Face adjacency across each edge (-1: boundary) and hard edges (boundary, dihedral above the
// crease angle, or listed in p.extraHardEdges); an error on non-manifold or misoriented edges.
std::string EdgesAndHardness(const TriData& net, const LoopSurfaceParams& p, std::vector<std::array<int, 3>>& adj,
                             std::vector<std::array<unsigned char, 3>>& hard) {
  const int nV = int(net.V.size()), nF = int(net.F.size());
  // edges: sort directed half-edges by undirected key
  struct HE { int64_t key; int f, k; };
  std::vector<HE> he(3 * size_t(nF));
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) {
      int a = net.F[f][k], b = net.F[f][(k + 1) % 3];
      he[3 * f + k] = {int64_t(std::min(a, b)) * nV + std::max(a, b), f, k};
    }
  std::sort(he.begin(), he.end(), [](const HE& x, const HE& y) { return x.key < y.key || (x.key == y.key && x.f < y.f); });
  adj.assign(nF, {-1, -1, -1});
  hard.assign(nF, {0, 0, 0});
  int nonManifold = 0, misoriented = 0, firstNM = -1, firstMis = -1;
  std::vector<Vec3> fn = FaceNormals(net);
  const double cosT = (p.creaseAngleDeg > 0 && p.creaseAngleDeg < 180) ? std::cos(p.creaseAngleDeg * M_PI / 180.0) : -2.0;
  for (size_t i = 0; i < he.size();) {
    size_t j = i;
    while (j < he.size() && he[j].key == he[i].key) ++j;
    if (j - i > 2) { ++nonManifold; if (firstNM < 0) firstNM = he[i].f; }
    else if (j - i == 2) {
      const HE &x = he[i], &y = he[i + 1];
      int ax = net.F[x.f][x.k], ay = net.F[y.f][y.k];
      if (ax == ay) { ++misoriented; if (firstMis < 0) firstMis = x.f; }
      adj[x.f][x.k] = y.f;
      adj[y.f][y.k] = x.f;
      double c = fn[x.f].dot(fn[y.f]);
      if (fn[x.f].squaredNorm() > 0 && fn[y.f].squaredNorm() > 0 && c < cosT) hard[x.f][x.k] = hard[y.f][y.k] = 1;
    } else {
      hard[he[i].f][he[i].k] = 1;  // boundary edges are hard
    }
    i = j;
  }
  if (nonManifold) { return std::to_string(nonManifold) + " non-manifold edges (shared by more than two faces; first at face " + std::to_string(firstNM) + ")"; }
  if (misoriented) { return std::to_string(misoriented) + " edges with inconsistently oriented faces (first at face " + std::to_string(firstMis) + "): orient the mesh first"; }
  for (const auto& e : p.extraHardEdges) {
    int a = e.first, b = e.second;
    if (a < 0 || b < 0 || a >= nV || b >= nV || a == b) { return "extra hard edge (" + std::to_string(a) + "," + std::to_string(b) + ") has invalid vertex indices"; }
    int64_t key = int64_t(std::min(a, b)) * nV + std::max(a, b);
    auto it = std::lower_bound(he.begin(), he.end(), key, [](const HE& x, int64_t k) { return x.key < k; });
    if (it == he.end() || it->key != key) { return "extra hard edge (" + std::to_string(a) + "," + std::to_string(b) + ") is not an edge of the mesh"; }
    for (; it != he.end() && it->key == key; ++it) hard[it->f][it->k] = 1;
  }
  return {};
}

// Exact limit mask of a dart i (a smooth vertex with one hard edge; its corner (f, k)): the left
// eigenvector (eigenvalue 1) of its 1-ring subdivision matrix. False where the ring is open.
bool DartMask(const TriData& net, int i, std::pair<int, int> corner, const std::vector<std::array<int, 3>>& adj,
              const std::vector<std::array<unsigned char, 3>>& hard, std::vector<std::pair<int, double>>& mask) {
  std::vector<int> ring;
  std::vector<char> ringHard;
  int f0 = corner.first, f = f0, k = corner.second;
  bool closed = false;
  for (int guard = 0; guard < 10000; ++guard) {
    ring.push_back(net.F[f][(k + 1) % 3]);
    ringHard.push_back(hard[f][k]);
    int g = adj[f][(k + 2) % 3];  // across edge (F[f][k+2], i)
    if (g < 0) break;
    f = g;
    k = 0;
    while (k < 3 && net.F[f][k] != i) ++k;
    if (f == f0) { closed = true; break; }
  }
  const int val = int(ring.size());
  if (!closed || val < 3) return false;  // cannot happen for a manifold interior vertex
  // S: row 0 vertex point, row 1+j edge point of edge (i, ring[j]); columns 0: i, 1+j: ring[j]
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(val + 1, val + 1);
  const double b = LoopBeta(val);
  S(0, 0) = 1.0 - val * b;
  for (int j = 0; j < val; ++j) S(0, 1 + j) = b;
  for (int j = 0; j < val; ++j) {
    if (ringHard[j]) { S(1 + j, 0) = 0.5; S(1 + j, 1 + j) = 0.5; continue; }
    S(1 + j, 0) = 0.375;
    S(1 + j, 1 + j) += 0.375;
    S(1 + j, 1 + (j + 1) % val) += 0.125;
    S(1 + j, 1 + (j + val - 1) % val) += 0.125;
  }
  Eigen::MatrixXd A(val + 2, val + 1);
  A.topRows(val + 1) = S.transpose() - Eigen::MatrixXd::Identity(val + 1, val + 1);
  A.row(val + 1).setOnes();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(val + 2);
  rhs(val + 1) = 1.0;
  Eigen::VectorXd l = A.colPivHouseholderQr().solve(rhs);
  mask.clear();
  mask.push_back({i, l(0)});
  for (int j = 0; j < val; ++j) mask.push_back({ring[j], l(1 + j)});
  return true;
}

}  // namespace

// The patches of every face (§2): a regular face's box-spline tile, an irregular face's
// subdivision tree down to cacheDepth (TriCache); in parallel, face by face.
void LoopSurface::Impl::BuildPatches(const TriData& net, const std::vector<LoopVertexType>& vtype,
                                     const std::vector<std::array<unsigned char, 3>>& hard, const Adjacency& vf,
                                     int cacheDepth, std::vector<char>& isReg, std::vector<Patch>& tmpPatch) {
  const int nF = int(net.F.size());
  cache.resize(nF);
  isReg.assign(nF, 0);
  tmpPatch.assign(nF, Patch());
#pragma omp parallel for schedule(dynamic, 64)
  for (int f = 0; f < nF; ++f) {
    // local net: faces incident to the corners of f
    LNet n;
    std::vector<int> faces;
    for (int k = 0; k < 3; ++k)
      for (const int* g = vf.Begin(net.F[f][k]); g != vf.End(net.F[f][k]); ++g)
        if (std::find(faces.begin(), faces.end(), *g) == faces.end()) faces.push_back(*g);
    std::vector<std::pair<int, int>> map;  // global -> local
    auto loc = [&](int gv) {
      for (auto& m : map)
        if (m.first == gv) return m.second;
      int id = int(n.P.size());
      map.push_back({gv, id});
      n.P.push_back(net.V[gv]);
      n.type.push_back((unsigned char)vtype[gv]);
      return id;
    };
    for (int k = 0; k < 3; ++k) loc(net.F[f][k]);
    for (int g : faces) {
      Tri t = {loc(net.F[g][0]), loc(net.F[g][1]), loc(net.F[g][2])};
      if (g == f) n.target = int(n.F.size());
      n.F.push_back(t);
      n.H.push_back(hard[g]);
    }
    Vec3 X[12];
    if (Gather(n, X)) {
      isReg[f] = 1;
      tmpPatch[f] = MakePatch(X);
    } else {
      BuildNode(cache[f], n, 0, cacheDepth);
    }
  }
}

// Flattens the patches into the arena (face order; per face breadth-first), frees the trees and
// indexes the nets whose ring is self-similar (one Ring per topology); returns the number of
// irregular faces.
int LoopSurface::Impl::Flatten(int nF, const std::vector<char>& isReg, const std::vector<Patch>& tmpPatch) {
  // flatten into the arena (face order; per face breadth-first)
  int numIrregularFaces_ = 0;
  size_t nTiles = 0, nNodes = 0, nNets = 0;
  for (int f = 0; f < nF; ++f) {
    if (isReg[f]) { ++nTiles; continue; }
    ++numIrregularFaces_;
    nTiles += cache[f].patches.size();
    nNodes += cache[f].nodes.size();
    nNets += cache[f].nets.size();
  }
  Impl& I = *this;
  I.root.assign(nF, 0);
  I.tiles.reserve(nTiles);
  I.nodes.reserve(nNodes);
  I.nets.reserve(nNets);
  for (int f = 0; f < nF; ++f) {
    if (isReg[f]) {
      I.root[f] = -1 - int32_t(I.tiles.size());
      I.tiles.push_back(tmpPatch[f]);
      continue;
    }
    TriCache& tc = I.cache[f];
    // BFS over the DFS tree; a node that is a tile or a net becomes a leaf code
    auto codeOf = [&](int node, std::vector<int>& queue) -> int32_t {
      const Node& nd = tc.nodes[node];
      if (nd.patch >= 0) { I.tiles.push_back(tc.patches[nd.patch]); return -1 - int32_t(I.tiles.size() - 1); }
      if (nd.net >= 0) { I.nets.push_back(std::move(tc.nets[nd.net])); return kNetBase + int32_t(I.nets.size() - 1); }
      queue.push_back(node);
      return int32_t(I.nodes.size() + queue.size() - 1);  // provisional: fixed below
    };
    std::vector<int> queue;
    int32_t rc = codeOf(0, queue);
    const int32_t base = int32_t(I.nodes.size());
    I.root[f] = rc >= 0 ? base : rc;
    // nodes are appended in queue order, so queue position q <-> node base + q
    for (size_t q = 0; q < queue.size(); ++q) {
      std::array<int32_t, 4> ch;
      for (int c = 0; c < 4; ++c) {
        int32_t code = codeOf(tc.nodes[queue[q]].child[c], queue);
        ch[c] = code >= 0 ? base + int32_t(queue.size() - 1) : code;
      }
      I.nodes.push_back(ch);
    }
    tc = TriCache();
  }
  std::vector<TriCache>().swap(I.cache);
  {
    std::unordered_map<std::string, int> cfg;
    I.netRing.assign(I.nets.size(), -1);
    for (size_t i = 0; i < I.nets.size(); ++i) {
      std::string key = TopologyKey(I.nets[i]);
      auto it = cfg.find(key);
      if (it == cfg.end()) {
        Ring r;
        int id = -1;
        if (BuildRing(I.nets[i], r)) { id = int(I.rings.size()); I.rings.push_back(std::move(r)); }
        it = cfg.emplace(std::move(key), id).first;
      }
      I.netRing[i] = it->second;
    }
  }
  return numIrregularFaces_;
}

namespace {
// Transparent huge pages for the tile arena: random queries otherwise miss the TLB on most tiles.
void AdviseHugePages(LoopSurface::Impl& I) {
#ifdef __linux__
  {
    const size_t huge = size_t(2) << 20;
    uintptr_t b = reinterpret_cast<uintptr_t>(I.tiles.data()), e = b + I.tiles.size() * sizeof(Patch);
    uintptr_t hb = (b + huge - 1) & ~(huge - 1), he = e & ~(huge - 1);
    if (he > hb) madvise(reinterpret_cast<void*>(hb), he - hb, MADV_HUGEPAGE);
  }
#endif
}

// EstimateLoopSurfaceMemoryMb's constants (bytes), fitted to what was measured: the growth of the
// peak resident memory while the surface is built (2026-12-07). Per irregular triangle 1.7 kB with
// no cached level, 4.5 kB with one, 4.7 kB per further level; per box-spline triangle 0.7 kB.
// bunny00 (75 408 triangles, 66 563 irregular) at depth 0 / 1 / 2 / 3 / 4 / 6: 106 / 255 / 549 /
// 891 / 1 193 / 1 702 MB; elephant (5 558, 5 109) at 0 / 2 / 4 / 6 / 10: 8 / 54 / 95 / 135 / 219 MB;
// armadillo (52 000, 49 058) at 2: 437 MB; fandisk (12 946, 4 590) at 2: 43 MB. The estimates
// from the constructor's count of irregular triangles (CountBoxSplineFaces, an upper bound): bunny00
// +9 / +14 / +7 / 0 / -1 / +5 %, elephant +5 / -14 / -2 / +3 / +7 %, armadillo -1 %, fandisk +41 %
// (its patches along straight creases counted as irregular); the 20 % of the available memory that
// CheckMemory leaves covers the ones a little low (docs/loop.md "Memory").
constexpr double kLoopBytesIrregularDepth0 = 1700;
constexpr double kLoopBytesIrregularDepth1 = 4500;
constexpr double kLoopBytesIrregularPerLevel = 4700;
constexpr double kLoopBytesRegular = 700;

// Triangles that are box-spline patches for certain: three interior smooth corners of valence 6
// with no hard edge. (A straight crease through a patch is one too; counted as irregular here, so
// that the estimate built on this count is an upper bound.)
long CountBoxSplineFaces(const TriData& net, const std::vector<LoopVertexType>& vtype,
                         const std::vector<std::vector<int>>& hardNb, const Adjacency& vf) {
  long n = 0;
  for (const Tri& t : net.F) {
    bool regular = true;
    for (int k = 0; k < 3 && regular; ++k)
      regular = vtype[t[k]] == LoopVertexType::Smooth && hardNb[t[k]].empty() && vf.Count(t[k]) == 6;
    n += regular ? 1 : 0;
  }
  return n;
}

}  // namespace

double EstimateLoopSurfaceMemoryMb(long irregularFaces, long regularFaces, int cacheDepth) {
  const double perIrregular = cacheDepth <= 0 ? kLoopBytesIrregularDepth0
                                              : kLoopBytesIrregularDepth1 + kLoopBytesIrregularPerLevel * (cacheDepth - 1);
  return (perIrregular * double(irregularFaces) + kLoopBytesRegular * double(regularFaces)) / (1024.0 * 1024.0);
}

LoopSurface::LoopSurface(const TriData& net, const LoopSurfaceParams& p) : net_(net), params_(p), impl_(new Impl) {
  const int nV = int(net.V.size()), nF = int(net.F.size());
  error_ = CheckNet(net, p);
  if (!error_.empty()) return;
  error_ = EdgesAndHardness(net, p, adj_, hard_);
  if (!error_.empty()) return;
  impl_->diag = BBoxDiagonal(net.V);
  // vertex types
  impl_->vv = VertexVertexAdjacency(net.F, nV);
  Adjacency vf = VertexFaceAdjacency(net.F, nV);
  impl_->hardNb.assign(nV, {});
  vcorner_.assign(nV, {-1, -1});
  numHardEdges_ = 0;
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) {
      if (vcorner_[net.F[f][k]].first < 0) vcorner_[net.F[f][k]] = {f, k};
      if (!hard_[f][k]) continue;
      int a = net.F[f][k], b = net.F[f][(k + 1) % 3];
      if (adj_[f][k] >= 0 && adj_[f][k] < f) continue;  // count interior edges once
      impl_->hardNb[a].push_back(b);
      impl_->hardNb[b].push_back(a);
      ++numHardEdges_;
    }
  vtype_.assign(nV, LoopVertexType::Smooth);
  for (int i = 0; i < nV; ++i) {
    int nf = vf.Count(i), nn = impl_->vv.Count(i), nh = int(impl_->hardNb[i].size());
    int boundary = 0;
    for (const int* f = vf.Begin(i); f != vf.End(i); ++f)
      for (int k = 0; k < 3; ++k)
        if (adj_[*f][k] < 0 && (net.F[*f][k] == i || net.F[*f][(k + 1) % 3] == i)) ++boundary;
    bool manifold = (boundary == 0 && nf == nn) || (boundary == 2 && nn == nf + 1);
    if (nf == 0) vtype_[i] = LoopVertexType::Smooth;
    else if (!manifold || nh > 2) vtype_[i] = LoopVertexType::Corner;
    else if (nh == 2) vtype_[i] = LoopVertexType::Crease;
    else vtype_[i] = LoopVertexType::Smooth;  // 0 hard edges or a dart
    // (a Corner with fewer than 3 hard edges is a non-manifold vertex: fixed all the same)
  }
  // exact limit masks of darts: left eigenvector (eigenvalue 1) of the 1-ring subdivision matrix
  for (int i = 0; i < nV; ++i) {
    if (vtype_[i] != LoopVertexType::Smooth || impl_->hardNb[i].empty() || vf.Count(i) == 0) continue;
    std::vector<std::pair<int, double>> mask;
    if (DartMask(net, i, vcorner_[i], adj_, hard_, mask)) impl_->dartMasks.push_back({i, std::move(mask)});
  }
  // patches
  impl_->maxDepth = std::max(1, std::min(p.maxDepth, 40));
  // the deepest cache up to p.cacheDepth that fits the memory (a 5 M-triangle scan at depth 2: ~40 GB)
  const long regular = CountBoxSplineFaces(net, vtype_, impl_->hardNb, vf), irregular = nF - regular;
  const std::string what = "the Loop surface of " + std::to_string(nF) + " triangles (" + std::to_string(irregular) +
                           " of them next to an extraordinary or crease vertex)";
  int cacheDepth = RequestedCacheDepth(p);
  for (;; --cacheDepth) {
    error_ = CheckMemory(EstimateLoopSurfaceMemoryMb(irregular, regular, cacheDepth), p.maxMemoryMb, what);
    if (error_.empty() || cacheDepth == 0) break;
  }
  if (!error_.empty()) {
    error_ += "; decimate the mesh first (Simplification: Quadric Edge Collapse Decimation)";
    return;
  }
  cacheDepth_ = cacheDepth;
  std::vector<char> isReg;
  std::vector<Patch> tmpPatch;
  impl_->BuildPatches(net, vtype_, hard_, vf, cacheDepth, isReg, tmpPatch);
  numIrregularFaces_ = impl_->Flatten(nF, isReg, tmpPatch);
  AdviseHugePages(*impl_);
}

int LoopSurface::NumCornerVertices() const {
  int c = 0;
  for (auto t : vtype_) c += t == LoopVertexType::Corner;
  return c;
}

bool LoopSurface::FaceIsRegular(int f) const { return IsTile(impl_->root[f]); }

size_t LoopSurface::CacheBytes() const {
  size_t b = impl_->tiles.size() * sizeof(Patch) + impl_->nodes.size() * sizeof(impl_->nodes[0]) + impl_->root.size() * 4;
  for (const auto& n : impl_->nets) b += n.P.size() * (sizeof(Vec3) + 1) + n.F.size() * (sizeof(Tri) + 3);
  for (const auto& r : impl_->rings) b += (r.S.size() + 3 * 12 * size_t(r.n)) * sizeof(double);
  return b;
}

double LoopSurface::NetDiagonal() const { return impl_->diag; }

namespace {

// One level down into child c of the current triangle: its parameters (the affine map kA, kB,
// clamped onto the triangle) and the chain rule J of the derivatives.
inline void Descend(int c, double& v, double& w, double J[2][2]) {
  double nv = kA[c][0][0] * v + kA[c][0][1] * w + kB[c][0];
  double nw = kA[c][1][0] * v + kA[c][1][1] * w + kB[c][1];
  v = nv; w = nw;
  ClampParam(v, w);
  StepJ(J, c);
}

// The control points, row-major `rows` x n, times the n points of P (xyz interleaved) into out.
inline void MultiplyPoints(const double* rows, int count, int n, const double* P, double* out) {
  for (int i = 0; i < count; ++i) {
    double x = 0, y = 0, z = 0;
    const double* row = rows + size_t(i) * n;
    for (int j = 0; j < n; ++j) { x += row[j] * P[3 * j]; y += row[j] * P[3 * j + 1]; z += row[j] * P[3 * j + 2]; }
    out[3 * i] = x; out[3 * i + 1] = y; out[3 * i + 2] = z;
  }
}

// A self-similar corner net (net index `k`, its ring R): one matrix-vector product per level, no
// allocation, down to the level whose child leaves the corner (evaluated as a box-spline patch).
void EvalSelfSimilarCorner(const LoopSurface::Impl& I, int k, double v, double w, int order, double J[2][2],
                           int& depth, LoopEval& e) {
  const LNet& n0 = I.nets[k];
  const Ring& R = I.rings[I.netRing[k]];
  const int n = R.n;
  double buf[2][96 * 3];
  double* P = buf[0];
  double* Q = buf[1];
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) P[3 * i + d] = n0.P[i][d];
  for (;;) {
    int c = depth >= I.maxDepth ? 3 : ChildOf(v, w);  // the nudge (Fig. 8)
    Descend(c, v, w, J);
    ++depth;
    if (c != R.kc || depth > I.maxDepth + 2) {
      if (c == R.kc) c = 3;  // cannot happen (the nudge picks the regular centre child)
      double X12[12 * 3];
      MultiplyPoints(R.T[c].data(), 12, n, P, X12);
      Vec3 X[12];
      for (int m = 0; m < 12; ++m) X[m] = Vec3(X12[3 * m], X12[3 * m + 1], X12[3 * m + 2]);
      EvalPatch(MakePatch(X), v, w, order, e);
      return;
    }
    MultiplyPoints(R.S.data(), n, n, P, Q);
    std::swap(P, Q);
  }
}

// Any other net (index `k`): subdivided on the fly until its triangle is regular (a box-spline
// patch).
void EvalBySubdivision(const LoopSurface::Impl& I, int k, double v, double w, int order, double J[2][2], int& depth,
                       LoopEval& e) {
  LNet n = I.nets[k];
  Vec3 X[12];
  for (;;) {
    if (Gather(n, X)) {
      EvalPatch(MakePatch(X), v, w, order, e);
      return;
    }
    int c = depth >= I.maxDepth ? 3 : ChildOf(v, w);  // the nudge (Fig. 8)
    Descend(c, v, w, J);
    n = Subdivide(n, c);
    ++depth;
    if (depth > I.maxDepth + 2) {  // cannot happen for a valid net: bail out safely
      EvalPatch(MakePatch(X), v, w, 0, e);
      return;
    }
  }
}

}  // namespace

bool LoopSurface::Evaluate(int face, double v, double w, LoopEval& e, int order) const {
  if (!Ok() || face < 0 || face >= NumFaces()) return false;
  ClampParam(v, w);
  const Impl& I = *impl_;
  int32_t code = I.root[face];
  if (IsTile(code)) {
    EvalPatch(I.tiles[-1 - code], v, w, order, e);
    e.depth = 0;
  } else {
    double J[2][2] = {{1, 0}, {0, 1}};
    int depth = 0;
    while (code >= 0) {  // the precomputed levels
      const int c = ChildOf(v, w);
      Descend(c, v, w, J);
      code = I.nodes[code][c];
      ++depth;
    }
    if (IsTile(code))
      EvalPatch(I.tiles[-1 - code], v, w, order, e);
    else if (I.netRing[code - kNetBase] >= 0)
      EvalSelfSimilarCorner(I, code - kNetBase, v, w, order, J, depth, e);
    else
      EvalBySubdivision(I, code - kNetBase, v, w, order, J, depth, e);
    ApplyJacobian(J, e, order);
    e.depth = depth;
  }
  if (order >= 1) {
    Vec3 n = e.Dv.cross(e.Dw);
    double l = n.norm();
    e.N = l > 0 ? Vec3(n / l) : Vec3::Zero();
  }
  return true;
}

Vec3 LoopSurface::Position(int face, double v, double w) const {
  LoopEval e;
  Evaluate(face, v, w, e, 0);
  return e.P;
}

LoopCurvature LoopSurface::Curvature(int face, double v, double w, LoopEval* eval) const {
  LoopEval e;
  Evaluate(face, v, w, e, 2);
  if (eval) *eval = e;
  return CurvatureFromDerivatives(e);
}

void LoopSurface::LimitMatrixTriplets(std::vector<int>& rows, std::vector<int>& cols, std::vector<double>& wts) const {
  rows.clear(); cols.clear(); wts.clear();
  const int nV = NumVertices();
  for (int i = 0; i < nV; ++i) {
    auto add = [&](int j, double x) { rows.push_back(i); cols.push_back(j); wts.push_back(x); };
    int k = impl_->vv.Count(i);
    if (vtype_[i] == LoopVertexType::Corner || k == 0) { add(i, 1.0); continue; }
    if (vtype_[i] == LoopVertexType::Crease) {
      add(i, 4.0 / 6.0);
      for (int j : impl_->hardNb[i]) add(j, 1.0 / 6.0);
      continue;
    }
    if (const auto* dm = impl_->DartMask(i)) {
      for (const auto& e : *dm) add(e.first, e.second);
      continue;
    }
    double chi = 1.0 / (k + 3.0 / (8.0 * LoopBeta(k)));
    add(i, 1.0 - k * chi);
    for (const int* j = impl_->vv.Begin(i); j != impl_->vv.End(i); ++j) add(*j, chi);
  }
}

std::vector<Vec3> LoopSurface::VertexLimits(const std::vector<Vec3>& X) const {
  std::vector<int> r, c;
  std::vector<double> w;
  LimitMatrixTriplets(r, c, w);
  std::vector<Vec3> out(X.size(), Vec3::Zero());
  for (size_t t = 0; t < r.size(); ++t) out[r[t]] += w[t] * X[c[t]];
  return out;
}

Vec3 LoopSurface::VertexLimit(int i) const {
  const int k = impl_->vv.Count(i);
  const Vec3& x = net_.V[i];
  if (vtype_[i] == LoopVertexType::Corner || k == 0) return x;
  if (vtype_[i] == LoopVertexType::Crease) {
    Vec3 s = 4.0 * x;
    for (int j : impl_->hardNb[i]) s += net_.V[j];
    return s / 6.0;
  }
  if (const auto* dm = impl_->DartMask(i)) {
    Vec3 s = Vec3::Zero();
    for (const auto& e : *dm) s += e.second * net_.V[e.first];
    return s;
  }
  double chi = 1.0 / (k + 3.0 / (8.0 * LoopBeta(k)));
  Vec3 s = (1.0 - k * chi) * x;
  for (const int* j = impl_->vv.Begin(i); j != impl_->vv.End(i); ++j) s += chi * net_.V[*j];
  return s;
}

}  // namespace vcgext
