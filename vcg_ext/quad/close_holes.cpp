/// \file close_holes.cpp
/// Small holes closed by vcglib's ear cutting (close_holes.h). The loops are found and chosen on
/// the arrays; vcglib sees only the faces around the chosen loops (a closed or lightly holed dense
/// scan costs one pass over its faces).
#include "vcg_ext/quad/close_holes.h"

#include <vcg/complex/algorithms/hole.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/complex.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/quad/quad_simplify.h"
#include "vcg_ext/quad/scan_artifacts.h"

namespace vcgext {

namespace {
class HVertex;
class HFace;
struct HTypes : public vcg::UsedTypes<vcg::Use<HVertex>::AsVertexType, vcg::Use<HFace>::AsFaceType> {};
class HVertex : public vcg::Vertex<HTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d, vcg::vertex::BitFlags> {};
class HFace : public vcg::Face<HTypes, vcg::face::VertexRef, vcg::face::Normal3d, vcg::face::FFAdj,
                               vcg::face::BitFlags> {};
class HMesh : public vcg::tri::TriMesh<std::vector<HVertex>, std::vector<HFace>> {
 public:
  HMesh() { attrn = 0; }  // (vcglib 2020.09 leaves it uninitialised)
};
using Hole = vcg::tri::Hole<HMesh>;

double Area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

double Area(const std::vector<Vec3>& V, const Tri& t) {
  return Area(V[size_t(t[0])], V[size_t(t[1])], V[size_t(t[2])]);
}

std::pair<int, int> Undirected(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// The corner k of t whose edge (t[k], t[k+1]) is the longest.
int LongestEdge(const std::vector<Vec3>& V, const Tri& t) {
  int k = 0;
  for (int j = 1; j < 3; ++j)
    if ((V[size_t(t[j])] - V[size_t(t[(j + 1) % 3])]).squaredNorm() >
        (V[size_t(t[k])] - V[size_t(t[(k + 1) % 3])]).squaredNorm())
      k = j;
  return k;
}

// The face of `faces` with the directed edge a -> b (from its corner c), or faces.size().
size_t FaceWith(const std::vector<Tri>& faces, int a, int b, int& c) {
  for (size_t u = 0; u < faces.size(); ++u)
    for (c = 0; c < 3; ++c)
      if (faces[u][c] == a && faces[u][(c + 1) % 3] == b) return u;
  return faces.size();
}

// Removes the triangles of no area from a hole's closing by edge flips. Ear cutting takes an
// ear of three collinear rim points when nothing else is left, and a rim of collinear runs is
// common: a holed mesh refined by edge midpoints (bunny00 with 2 % of its faces deleted, ×16:
// 101 of its 1 297 holes). In such a triangle (p, q, o) with p–q its longest edge, o lies on
// p–q; p–q is shared with the closing's triangle (q, p, d), and flipping it to o–d splits that
// triangle at o into two of positive area (unless d is on the line too: flipped again). An edge
// o–d the mesh already has (`edges`: those of the faces round the loops) or the closing has is
// not made. Returns whether every triangle has an area.
bool FlipOutDegenerate(const std::vector<Vec3>& V, const std::set<std::pair<int, int>>& edges,
                       std::vector<Tri>& closing) {
  auto uses = [&](int a, int b) {
    for (const Tri& f : closing)
      for (int k = 0; k < 3; ++k)
        if (Undirected(f[k], f[(k + 1) % 3]) == Undirected(a, b)) return true;
    return edges.count(Undirected(a, b)) > 0;
  };
  for (size_t round = 0; round < 4 * closing.size(); ++round) {
    size_t t = 0;
    while (t < closing.size() && Area(V, closing[t]) > 0) ++t;
    if (t == closing.size()) return true;
    const Tri tri = closing[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) return false;
    const int i = LongestEdge(V, tri);
    const int p = tri[i], q = tri[(i + 1) % 3], o = tri[(i + 2) % 3];
    int c = 0;
    const size_t u = FaceWith(closing, q, p, c);
    if (u == closing.size()) return false;  // p–q is on the rim
    const int d = closing[u][(c + 2) % 3];
    if (d == o || uses(o, d)) return false;
    closing[t] = Tri{o, p, d};
    closing[u] = Tri{d, q, o};
  }
  return false;
}

// Per vertex of `loop` at a position an earlier one of the loop has (the working copy's copies of
// a vertex where two holes touched, split apart to keep the mesh manifold): that earlier vertex,
// recorded in `into` (-1: none); whether there was one.
bool CopiesOnLoop(const std::vector<Vec3>& V, const std::vector<int>& loop, std::vector<int>& into) {
  std::vector<std::pair<std::array<double, 3>, int>> at;
  for (int v : loop) at.push_back({{V[size_t(v)].x(), V[size_t(v)].y(), V[size_t(v)].z()}, v});
  std::sort(at.begin(), at.end());
  bool any = false;
  for (size_t k = 1; k < at.size(); ++k)
    if (at[k].first == at[k - 1].first && at[k].second != at[k - 1].second) {
      const int first = into[size_t(at[k - 1].second)] >= 0 ? into[size_t(at[k - 1].second)] : at[k - 1].second;
      into[size_t(at[k].second)] = first;
      any = true;
    }
  return any;
}

// A loop's straight sides: its vertices where it turns by more than a degree. A run of collinear
// edges counts once, so a hole of a few missing triangles keeps its count when the mesh is refined
// by edge midpoints (bunny00 with 2 % of its faces deleted, ×16: 17 holes of 3-6 edges at x1 above
// 2 % of the diagonal have 12-24 edges).
int Sides(const std::vector<Vec3>& V, const std::vector<int>& loop) {
  const size_t n = loop.size();
  int sides = 0;
  for (size_t k = 0; k < n; ++k) {
    const Vec3 a = V[size_t(loop[k])] - V[size_t(loop[(k + n - 1) % n])];
    const Vec3 b = V[size_t(loop[(k + 1) % n])] - V[size_t(loop[k])];
    const double cross = a.cross(b).norm(), dot = a.dot(b);
    sides += !(dot > 0 && cross <= std::tan(M_PI / 180) * dot);
  }
  return sides;
}

// The holes to close (FindHoleLoops: not a piece's outline; manifold, below the size rule);
// `holes` counts the holes.
std::vector<std::vector<int>> SmallLoops(const TriData& m, const CloseHolesParams& p, int& holes) {
  std::vector<HoleLoop> loops = FindHoleLoops(m);
  holes = int(loops.size());
  std::vector<std::vector<int>> chosen;
  const double diag = BBoxDiagonal(m.V), maxDiag = p.maxDiagonalPercent / 100.0 * diag;
  for (HoleLoop& loop : loops) {
    const double d = loop.diagonal;
    if (!loop.manifold || loop.vertices.size() < 3) continue;
    if (d < maxDiag || (d < p.maxEdgesDiagonalPercent / 100.0 * diag && Sides(m.V, loop.vertices) <= p.maxEdges))
      chosen.push_back(std::move(loop.vertices));
  }
  return chosen;
}

// Whether most of a hole's closing triangles (by area) lie on the input: their centroid within a
// twentieth of the loop's radius of one of its faces. A loop round an island does (a piece cut
// out by cracks, the other sheet of a doubled wall), and a slit's closing over the flap beside it:
// closing them would double a sheet. A hole's own closing keeps its centroids a fifth of the
// radius or more from its rim (an ear's centroid is a third of its height off its edge).
bool DoublesASheet(const EmbreeScene& scene, const TriData& m, const std::vector<Tri>& closing,
                   const std::vector<int>& loop) {
  Vec3 c = Vec3::Zero();
  for (int v : loop) c += m.V[size_t(v)];
  c /= double(loop.size());
  double radius = 0;
  for (int v : loop) radius += (m.V[size_t(v)] - c).norm() / double(loop.size());
  double doubled = 0, total = 0;
  for (const Tri& t : closing) {
    const Vec3 &a = m.V[size_t(t[0])], &b = m.V[size_t(t[1])], &d = m.V[size_t(t[2])];
    const double area = Area(a, b, d);
    total += area;
    const Vec3 x = (a + b + d) / 3;
    const EmbreeScene::Hit h = scene.ClosestPoint(x, 0.05 * radius);  // (the radius prunes; it may return farther)
    if (h.valid && (h.point - x).norm() <= 0.05 * radius) doubled += area;
  }
  return doubled > 0.5 * total;
}

// The faces of `m` with a corner on one of `loops`, as a vcg mesh of the vertices they use
// (`local`: per vertex of m its index in h, or -1), with face-face adjacency and vertex normals:
// every loop vertex's whole star, all ear cutting looks at.
void AroundLoops(const TriData& m, const std::vector<std::vector<int>>& loops, HMesh& h, std::vector<int>& local,
                 std::vector<int>& global) {
  std::vector<char> onLoop(m.V.size(), 0);
  for (const auto& loop : loops)
    for (int v : loop) onLoop[size_t(v)] = 1;
  std::vector<size_t> faces;
  for (size_t f = 0; f < m.F.size(); ++f)
    if (onLoop[size_t(m.F[f][0])] || onLoop[size_t(m.F[f][1])] || onLoop[size_t(m.F[f][2])]) faces.push_back(f);
  local.assign(m.V.size(), -1);
  global.clear();
  for (size_t f : faces)
    for (int v : m.F[f])
      if (local[size_t(v)] < 0) {
        local[size_t(v)] = int(global.size());
        global.push_back(v);
      }
  auto vi = vcg::tri::Allocator<HMesh>::AddVertices(h, global.size());
  for (int v : global) (vi++)->P() = vcg::Point3d(m.V[size_t(v)].x(), m.V[size_t(v)].y(), m.V[size_t(v)].z());
  auto fi = vcg::tri::Allocator<HMesh>::AddFaces(h, faces.size());
  for (size_t f : faces) {
    for (int c = 0; c < 3; ++c) fi->V(c) = &h.vert[size_t(local[size_t(m.F[f][c])])];
    ++fi;
  }
  vcg::tri::UpdateTopology<HMesh>::FaceFace(h);
  vcg::tri::UpdateNormal<HMesh>::PerVertexNormalizedPerFaceNormalized(h);
}

// The border positions of `h` by their half-edge (local indices a -> b).
std::map<std::pair<int, int>, Hole::PosType> Borders(HMesh& h) {
  std::map<std::pair<int, int>, Hole::PosType> at;
  for (auto& f : h.face)
    for (int j = 0; j < 3; ++j)
      if (vcg::face::IsBorder(f, j))
        at[{int(f.V(j) - &h.vert[0]), int(f.V((j + 1) % 3) - &h.vert[0])}] = Hole::PosType(&f, j, f.V(j));
  return at;
}

// Where FillHoleEar starts on each loop: a border half-edge whose tail the loop passes once (not
// a joined vertex); null when h has no such border.
std::vector<Hole::PosType> LoopStarts(HMesh& h, const std::vector<std::vector<int>>& loops,
                                      const std::vector<int>& local) {
  const std::map<std::pair<int, int>, Hole::PosType> borders = Borders(h);
  std::vector<Hole::PosType> at;
  for (const auto& loop : loops) {
    size_t k = 0;
    while (k + 1 < loop.size() && std::count(loop.begin(), loop.end(), loop[k]) > 1) ++k;
    const auto b = borders.find({local[size_t(loop[k])], local[size_t(loop[(k + 1) % loop.size()])]});
    at.push_back(b != borders.end() ? b->second : Hole::PosType());
  }
  return at;
}

// The edges of h's faces (the faces round the loops), by global vertex index.
std::set<std::pair<int, int>> EdgesOf(const HMesh& h, const std::vector<int>& global) {
  std::set<std::pair<int, int>> edges;
  for (const auto& f : h.face)
    for (int c = 0; c < 3; ++c)
      edges.insert(Undirected(global[size_t(f.cV(c) - &h.vert[0])], global[size_t(f.cV((c + 1) % 3) - &h.vert[0])]));
  return edges;
}

// The live faces h gained from index `before` on, by global vertex index.
std::vector<Tri> ClosingOf(const HMesh& h, size_t before, const std::vector<int>& global) {
  std::vector<Tri> closing;
  for (size_t f = before; f < h.face.size(); ++f) {
    if (h.face[f].IsD()) continue;
    Tri t;
    for (int c = 0; c < 3; ++c) t[c] = global[size_t(h.face[f].cV(c) - &h.vert[0])];
    closing.push_back(t);
  }
  return closing;
}

// v, or the copy it is joined into (`into`, JoinCopies').
int Joined(const std::vector<int>& into, int v) { return into[size_t(v)] >= 0 ? into[size_t(v)] : v; }

// Per vertex the earlier copy of its point on one of `loops` it is to be joined into
// (CopiesOnLoop; -1: none), and the loop that joins it (`joined`).
std::vector<int> JoinCopies(const std::vector<Vec3>& V, const std::vector<std::vector<int>>& loops,
                            std::vector<int>& joined) {
  std::vector<int> into(V.size(), -1);
  joined.assign(V.size(), -1);
  for (size_t k = 0; k < loops.size(); ++k)
    if (CopiesOnLoop(V, loops[k], into))
      for (int v : loops[k])
        if (into[size_t(v)] >= 0 && joined[size_t(v)] < 0) joined[size_t(v)] = int(k);
  return into;
}

// The input with the closings of the loops `closed` after its faces, the copies those loops
// join (`joined`: per vertex the loop that joined it) joined again, the others apart (joined,
// an open loop's copies would pinch its rim into a non-manifold vertex); `into` keeps the joins
// made.
TriData Assemble(const TriData& input, const std::vector<int>& joinAll, const std::vector<int>& joined,
                 const std::vector<char>& closed, const std::vector<std::vector<Tri>>& closings,
                 std::vector<int>& into) {
  into = joinAll;
  for (size_t v = 0; v < into.size(); ++v)
    if (into[v] >= 0 && !closed[size_t(joined[v])]) into[v] = -1;
  TriData m;
  m.V = input.V;
  m.F = input.F;
  for (Tri& f : m.F)
    for (int& v : f) v = Joined(into, v);
  for (size_t k = 0; k < closings.size(); ++k)
    if (closed[k]) m.F.insert(m.F.end(), closings[k].begin(), closings[k].end());
  return m;
}

// The vertices (a non-manifold edge: its ends) that are non-manifold in `closed` (Assemble's)
// but not in `input`, found on the faces round the loops' vertices (`onLoop`) and their
// neighbours only: only there do stars and edges change, and the faces farther out are the
// same in both (the 1.2 M-triangle holed bunny: the whole closing 6.4 -> 1.4 s, where two
// passes over the whole mesh were most of it).
std::vector<int> NewNonManifold(const TriData& input, const TriData& closed, const std::vector<char>& onLoop) {
  std::vector<char> near = onLoop;
  for (const Tri& f : input.F)
    if (onLoop[size_t(f[0])] || onLoop[size_t(f[1])] || onLoop[size_t(f[2])])
      for (int v : f) near[size_t(v)] = 1;
  TriData a, b;
  a.V = input.V;
  b.V = closed.V;
  for (size_t f = 0; f < input.F.size(); ++f) {
    const Tri& t = input.F[f];
    if (!near[size_t(t[0])] && !near[size_t(t[1])] && !near[size_t(t[2])]) continue;
    a.F.push_back(t);
    b.F.push_back(closed.F[f]);
  }
  b.F.insert(b.F.end(), closed.F.begin() + std::ptrdiff_t(input.F.size()), closed.F.end());
  std::vector<int> before, after, fresh;
  int e = 0, v = 0;
  CountNonManifold(a, &e, &v, &before);
  CountNonManifold(b, &e, &v, &after);
  std::sort(before.begin(), before.end());
  for (int x : after)
    if (!std::binary_search(before.begin(), before.end(), x)) fresh.push_back(x);
  return fresh;
}

// Drops the joined vertices (`into` >= 0) from m; r.vertexMap: old -> new index.
void DropJoined(TriData& m, const std::vector<int>& into, CloseHolesResult& r) {
  r.vertexMap.assign(m.V.size(), -1);
  std::vector<Vec3> V;
  for (size_t v = 0; v < m.V.size(); ++v)
    if (into[v] < 0) {
      r.vertexMap[v] = int(V.size());
      V.push_back(m.V[v]);
    }
  for (size_t v = 0; v < m.V.size(); ++v)
    if (into[v] >= 0) r.vertexMap[v] = r.vertexMap[size_t(into[v])];
  for (Tri& f : m.F)
    for (int& v : f) v = r.vertexMap[size_t(v)];
  m.V = std::move(V);
}

// Each loop's closing (by ear cutting on the faces round the loops, copies joined: `joinAll`),
// and whether it is kept (`closed`): not when ear cutting failed or left a triangle of no area
// that no flip removes (r.skipped), nor round an island (r.islands).
std::vector<std::vector<Tri>> Closings(const TriData& input, const std::vector<int>& joinAll,
                                       const std::vector<std::vector<int>>& loopsIn, CloseHolesResult& r,
                                       std::vector<char>& closed) {
  TriData m = input;
  for (Tri& f : m.F)
    for (int& v : f) v = Joined(joinAll, v);
  std::vector<std::vector<int>> loops = loopsIn;
  for (auto& loop : loops)
    for (int& v : loop) v = Joined(joinAll, v);
  HMesh h;
  std::vector<int> local, global;
  AroundLoops(m, loops, h, local, global);
  std::vector<Hole::PosType> at = LoopStarts(h, loops, local);
  const std::set<std::pair<int, int>> edges = EdgesOf(h, global);
  const EmbreeScene scene(input);
  std::vector<HMesh::FacePointer*> update;  // FillHoleEar's added faces may move the vector
  for (auto& pos : at) update.push_back(&pos.f);
  std::vector<std::vector<Tri>> closings(loops.size());
  closed.assign(loops.size(), 0);
  for (size_t k = 0; k < loops.size(); ++k) {
    if (at[k].IsNull()) {
      ++r.skipped;
      continue;
    }
    const size_t before = h.face.size();
    Hole::FillHoleEar<vcg::tri::MinimumWeightEar<HMesh>>(h, at[k], update);
    closings[k] = ClosingOf(h, before, global);
    if (closings[k].empty() || !FlipOutDegenerate(m.V, edges, closings[k])) {
      ++r.skipped;
      continue;
    }
    if (scene.Ok() && DoublesASheet(scene, m, closings[k], loops[k])) {
      ++r.islands;
      continue;
    }
    closed[k] = 1;
    ++r.closed;
  }
  return closings;
}
}  // namespace

CloseHolesResult CloseSmallHoles(const TriData& input, const CloseHolesParams& p) {
  CloseHolesResult r;
  r.mesh = input;
  if (!(p.maxDiagonalPercent > 0) || input.F.empty()) return r;
  std::vector<std::vector<int>> loops = SmallLoops(input, p, r.holes);
  if (loops.empty()) return r;
  std::vector<char> onLoop(input.V.size(), 0);
  for (const auto& loop : loops)
    for (int v : loop) onLoop[size_t(v)] = 1;
  std::vector<int> joined;
  const std::vector<int> joinAll = JoinCopies(input.V, loops, joined);
  std::vector<char> closed;
  const std::vector<std::vector<Tri>> closings = Closings(input, joinAll, loops, r, closed);
  // a closing that pinches a vertex or an edge (ear cutting round a vertex the loop passes
  // several times) is undone, its loop left open, and the rest checked again
  std::vector<int> into;
  TriData m;
  for (int round = 0;; ++round) {
    m = Assemble(input, joinAll, joined, closed, closings, into);
    const std::vector<int> fresh = NewNonManifold(input, m, onLoop);
    if (fresh.empty()) break;
    if (round == 3) {
      r.closed = 0;
      r.refused = "closing them would make " + std::to_string(fresh.size()) + " vertices non-manifold";
      return r;
    }
    std::vector<char> bad(input.V.size(), 0);
    for (int v : fresh) bad[size_t(v)] = 1;
    for (size_t k = 0; k < loops.size(); ++k) {
      bool pinches = false;
      for (const Tri& t : closings[k]) pinches = pinches || bad[size_t(t[0])] || bad[size_t(t[1])] || bad[size_t(t[2])];
      if (closed[k] && pinches) {
        closed[k] = 0;
        --r.closed;
        ++r.pinched;
      }
    }
  }
  double added = 0;
  for (size_t k = 0; k < loops.size(); ++k)
    if (closed[k])
      for (const Tri& t : closings[k]) added += Area(input.V, t);
  r.closedAreaPct = 100.0 * added / std::max(TotalArea(input), 1e-300);
  // the joined copies leave the vertex array (vertexMap: old -> new index)
  for (int t : into) r.joinedVertices += t >= 0;
  if (r.joinedVertices > 0) DropJoined(m, into, r);
  r.mesh = std::move(m);
  return r;
}

CloseHolesResult CloseSmallHoles(WorkingCopy& w, const CloseHolesParams& p) {
  CloseHolesResult r = CloseSmallHoles(w.mesh, p);
  if (r.closed == 0) return r;
  if (!r.vertexMap.empty()) {
    for (int& v : w.liveToMesh)
      if (v >= 0) v = r.vertexMap[size_t(v)];
    std::vector<int> meshToLive(r.mesh.V.size(), -1);
    for (size_t v = w.meshToLive.size(); v-- > 0;) meshToLive[size_t(r.vertexMap[v])] = w.meshToLive[v];
    w.meshToLive = std::move(meshToLive);
  }
  w.mesh = r.mesh;
  return r;
}

}  // namespace vcgext
