// Pairing the faux-edge halves of a MeshLab pure-quad layer into quads (ImportQuads).
#include "vcg_ext/core/quad_pairing.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <functional>
#include <map>
#include <tuple>
#include <type_traits>
#include <utility>

#include "vcg_ext/core/edge_faces.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/union_find.h"

namespace vcgext {

namespace {

using QuadPairs = std::vector<std::pair<int, int>>;

// Unit normal of half i (zero when degenerate).
Vec3 HalfNormal(const FauxHalves& h, const QuadData& q, int i) {
  const auto& t = h.tris[i];
  Vec3 n = (q.V[t[1]] - q.V[t[0]]).cross(q.V[t[2]] - q.V[t[0]]);
  double l = n.norm();
  return l > 0 ? Vec3(n / l) : Vec3::Zero();
}

// Greedy pairing across each diagonal, by normal agreement (trivial for the usual 1:1 case).
// Marks the paired halves in `done`; returns the quads of diagonals shared by exactly two.
QuadPairs PairAcrossDiagonals(const FauxHalves& h, QuadData& out, std::vector<char>& done, int* ambiguousResolved) {
  // Faux edges keyed by their directed (from, to) pair; the partner has (to, from).
  std::map<std::pair<int, int>, std::vector<int>> fauxOf;
  for (size_t i = 0; i < h.tris.size(); ++i) {
    const auto& t = h.tris[i];
    const int slot = h.fauxSlot[i];
    fauxOf[{t[slot], t[(slot + 1) % 3]}].push_back(int(i));
  }
  QuadPairs twoByTwo;  // ambiguous diagonals shared by exactly two quads
  for (const auto& [key, side] : fauxOf) {
    if (key.first > key.second) continue;  // each diagonal once, from its (low, high) side
    auto it = fauxOf.find({key.second, key.first});
    const size_t n2 = it == fauxOf.end() ? 0 : it->second.size();
    if (n2 == 0) continue;
    const std::vector<int>& other = it->second;
    if (side.size() > 1 || n2 > 1)
      if (ambiguousResolved) ++*ambiguousResolved;
    std::vector<std::tuple<double, int, int>> cand;
    for (int i : side)
      for (int j : other) cand.emplace_back(-HalfNormal(h, out, i).dot(HalfNormal(h, out, j)), i, j);
    std::sort(cand.begin(), cand.end());
    if (side.size() == 2 && n2 == 2) twoByTwo.emplace_back(int(out.F.size()), int(out.F.size()) + 1);
    for (const auto& [score, i, j] : cand) {
      if (done[i] || done[j]) continue;
      done[i] = done[j] = 1;
      const auto& t = h.tris[i];
      const int k = h.fauxSlot[i];
      const int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
      const int d = h.tris[j][(h.fauxSlot[j] + 2) % 3];
      out.F.push_back({a, d, b, c});  // boundary a→d→b→c (the diagonal a–b removed)
    }
  }
  return twoByTwo;
}

// Normals can mislead (folded regions); the pairing that is wrong splits the quad fan of a
// diagonal end into two (a non-manifold vertex). For diagonals shared by two quads, keep the
// pairing with fewer fans at the diagonal's ends (two passes: groups can share vertices).
void UntangleSharedDiagonals(const QuadPairs& twoByTwo, QuadData& out) {
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

}  // namespace

std::string PairFauxHalves(const FauxHalves& h, QuadData& out, int* ambiguousResolved) {
  if (ambiguousResolved) *ambiguousResolved = 0;
  std::vector<char> done(h.tris.size(), 0);
  const QuadPairs twoByTwo = PairAcrossDiagonals(h, out, done, ambiguousResolved);
  if (!twoByTwo.empty()) UntangleSharedDiagonals(twoByTwo, out);
  int unmatched = 0;
  for (size_t i = 0; i < h.tris.size(); ++i) unmatched += !done[i];
  if (unmatched > 0)
    return "the control layer is not pure-quad: " + std::to_string(unmatched) +
           " faux edges have no consistently oriented partner triangle";
  return "";
}

namespace {

// Why `shared` faux edges are run the same way by two triangles: edges of more than two triangles
// (a non-manifold control mesh; what is left once the faces were oriented, OrientFauxTriangles), or
// faces of inconsistent orientation.
std::string SharedFauxEdgesError(const FauxTriangles& t, int shared) {
  std::map<std::pair<int, int>, int> triangles;  // undirected edge -> triangles on it
  for (const auto& f : t.tris)
    for (int k = 0; k < 3; ++k) ++triangles[std::minmax(f[k], f[(k + 1) % 3])];
  int nonManifold = 0;
  for (size_t i = 0; i < t.tris.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (t.faux[i][k]) nonManifold += triangles[std::minmax(t.tris[i][k], t.tris[i][(k + 1) % 3])] > 2;
  if (nonManifold > 0)
    return std::to_string(shared) + " faux edges are run the same way by two triangles: " +
           std::to_string(nonManifold) +
           " triangles have a faux edge shared by more than two triangles (a non-manifold control mesh: Filters > "
           "Cleaning and Repairing > Repair non Manifold Edges)";
  return std::to_string(shared) +
         " faux edges are run the same way by two triangles (faces of inconsistent orientation: Filters > "
         "Normals, Curvatures and Orientation > Re-Orient all faces coherently)";
}

// The triangles of each polygon of `t` (joined across faux edges), in the order of their first
// triangle; "" or what is wrong with the faux edges.
std::string FauxGroups(const FauxTriangles& t, std::vector<std::vector<int>>& groups) {
  const int n = int(t.tris.size());
  std::map<std::pair<int, int>, int> fauxAt;  // directed faux edge -> its triangle
  int shared = 0, unpaired = 0;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      if (t.faux[i][k]) shared += !fauxAt.emplace(std::make_pair(t.tris[i][k], t.tris[i][(k + 1) % 3]), i).second;
  UnionFind sets(n);
  for (const auto& [e, i] : fauxAt) {
    const auto partner = fauxAt.find({e.second, e.first});
    if (partner == fauxAt.end()) ++unpaired;
    else sets.Unite(i, partner->second);
  }
  if (shared > 0) return SharedFauxEdgesError(t, shared);
  if (unpaired > 0) return std::to_string(unpaired) + " faux edges have no consistently oriented partner triangle";
  std::vector<int> slot(n, -1);
  for (int i = 0; i < n; ++i) {
    int& g = slot[sets.Find(i)];
    if (g < 0) {
      g = int(groups.size());
      groups.emplace_back();
    }
    groups[g].push_back(i);
  }
  return "";
}

// The boundary loop of one group of triangles (its non-faux edges chained), or empty when they
// are not one loop through n distinct corners for n - 2 triangles.
std::vector<int> PolygonLoop(const FauxTriangles& t, const std::vector<int>& group) {
  std::map<int, int> next;
  int first = -1;
  for (int i : group)
    for (int k = 0; k < 3; ++k) {
      if (t.faux[i][k]) continue;
      const int a = t.tris[i][k], b = t.tris[i][(k + 1) % 3];
      if (!next.emplace(a, b).second) return {};  // a corner twice: not a simple loop
      if (first < 0) first = a;
    }
  if (next.size() != group.size() + 2) return {};
  std::vector<int> loop{first};
  for (int v = next[first]; v != first; v = next[v]) {
    if (loop.size() == next.size() || next.count(v) == 0) return {};
    loop.push_back(v);
  }
  return loop.size() == next.size() ? loop : std::vector<int>{};
}

}  // namespace

int OrientFauxTriangles(FauxTriangles& t, int* nonOrientable) {
  if (nonOrientable) *nonOrientable = 0;
  for (const Tri& f : t.tris)
    if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) return 0;  // no orientation to agree on: the readers say
  std::vector<Tri> F = t.tris;
  int components = 0, bad = 0;
  const int flipped = OrientComponents(F, BuildEdgeFaces(F), &components, &bad);
  if (nonOrientable) *nonOrientable = bad;
  for (size_t i = 0; i < F.size(); ++i)
    if (F[i] != t.tris[i]) {  // (a, b, c) -> (a, c, b): edge 0 is now a-c (was edge 2), edge 2 b-a (was 0)
      t.tris[i] = F[i];
      std::swap(t.faux[i][0], t.faux[i][2]);
    }
  return flipped;
}

std::string PolygonsFromFauxTriangles(const FauxTriangles& t, std::vector<std::vector<int>>& polys) {
  std::vector<std::vector<int>> groups;
  std::string err = FauxGroups(t, groups);
  if (!err.empty()) return err;
  int bad = 0;
  for (const auto& g : groups) {
    std::vector<int> loop = PolygonLoop(t, g);
    if (loop.empty()) ++bad;
    else polys.push_back(std::move(loop));
  }
  if (bad > 0)
    return std::to_string(bad) +
           " polygons are not one loop of edges round their corners (a hole or an inner vertex among faux edges)";
  return "";
}

namespace {
// A coordinate as a MeshLab layer stores it: MESHLAB_SCALAR (CMakeLists.txt's FITMAP_SCALAR),
// float for MeshLab 2020.09's CMeshO, double for the 2025 build that PyMeshLab loads.
#if defined(MESHLAB_SCALAR)
using LayerScalar = MESHLAB_SCALAR;
#else
using LayerScalar = float;
#endif
double AsLayerStores(double x) {
  if constexpr (std::is_same_v<LayerScalar, float>) return RoundedToFloat(x);
  return x;
}
}  // namespace

QuadData LayerRoundTrip(const QuadData& q) {
  QuadData out;
  out.V.reserve(q.V.size());
  for (const Vec3& v : q.V) out.V.emplace_back(AsLayerStores(v[0]), AsLayerStores(v[1]), AsLayerStores(v[2]));
  ApplyInputCoordinatePrecision(out.V);  // and as the fit filter's reader takes them from the layer
  const std::vector<int> start = FreeDiagonalStarts(q);
  FauxHalves h;
  for (size_t i = 0; i < q.F.size(); ++i) {
    const auto& f = q.F[i];
    const int s = start[i];  // ExportQuads' halves: the diagonal s-(s+2) is faux
    h.tris.push_back({f[s], f[s + 1], f[s + 2]});
    h.fauxSlot.push_back(2);
    h.tris.push_back({f[s], f[s + 2], f[(s + 3) % 4]});
    h.fauxSlot.push_back(0);
  }
  if (!PairFauxHalves(h, out, nullptr).empty()) out.F.clear();
  return out;
}

}  // namespace vcgext
