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
#include <map>
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
    if (d < maxDiag || (int(loop.vertices.size()) <= p.maxEdges && d < p.maxEdgesDiagonalPercent / 100.0 * diag))
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

// Joins the copies of a point on each of `loops` (CopiesOnLoop) in m's faces and in the loops;
// per vertex the vertex it was joined into (-1: none).
std::vector<int> JoinCopies(TriData& m, std::vector<std::vector<int>>& loops) {
  std::vector<int> into(m.V.size(), -1);
  bool any = false;
  for (const auto& loop : loops) any = CopiesOnLoop(m.V, loop, into) || any;
  if (!any) return into;
  auto to = [&](int v) { return into[size_t(v)] >= 0 ? into[size_t(v)] : v; };
  for (Tri& f : m.F)
    for (int& v : f) v = to(v);
  for (auto& loop : loops)
    for (int& v : loop) v = to(v);
  return into;
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
}  // namespace

CloseHolesResult CloseSmallHoles(const TriData& input, const CloseHolesParams& p) {
  CloseHolesResult r;
  r.mesh = input;
  if (!(p.maxDiagonalPercent > 0) || input.F.empty()) return r;
  std::vector<std::vector<int>> loops = SmallLoops(input, p, r.holes);
  if (loops.empty()) return r;
  // a small hole through two copies of one point: the copies are joined again first (vcglib's
  // ear cutting closes a loop through a vertex twice; closed, that vertex is manifold again)
  TriData m = input;
  const std::vector<int> into = JoinCopies(m, loops);
  HMesh h;
  std::vector<int> local, global;
  AroundLoops(m, loops, h, local, global);
  const std::map<std::pair<int, int>, Hole::PosType> borders = Borders(h);
  std::vector<Hole::PosType> at;
  for (const auto& loop : loops) {
    // start on a half-edge whose tail the loop passes once (not a joined vertex)
    size_t k = 0;
    while (k + 1 < loop.size() && std::count(loop.begin(), loop.end(), loop[k]) > 1) ++k;
    const auto b = borders.find({local[size_t(loop[k])], local[size_t(loop[(k + 1) % loop.size()])]});
    at.push_back(b != borders.end() ? b->second : Hole::PosType());
  }
  const EmbreeScene scene(input);
  std::vector<HMesh::FacePointer*> update;  // FillHoleEar's added faces may move the vector
  for (auto& pos : at) update.push_back(&pos.f);
  // each hole's closing triangles (a range at the end of h.face), kept unless one is degenerate
  double added = 0;
  for (size_t k = 0; k < loops.size(); ++k) {
    if (at[k].IsNull()) {
      ++r.skipped;
      continue;
    }
    const size_t before = h.face.size();
    Hole::FillHoleEar<vcg::tri::MinimumWeightEar<HMesh>>(h, at[k], update);
    std::vector<Tri> closing;
    double area = 0;
    for (size_t f = before; f < h.face.size(); ++f) {
      if (h.face[f].IsD()) continue;
      Tri t;
      for (int c = 0; c < 3; ++c) t[c] = global[size_t(h.face[f].V(c) - &h.vert[0])];
      const double a = Area(m.V[size_t(t[0])], m.V[size_t(t[1])], m.V[size_t(t[2])]);
      area = a > 0 && area >= 0 ? area + a : -1;
      closing.push_back(t);
    }
    if (area < 0 || closing.empty()) {
      ++r.skipped;
      continue;
    }
    if (scene.Ok() && DoublesASheet(scene, m, closing, loops[k])) {
      ++r.islands;
      continue;
    }
    m.F.insert(m.F.end(), closing.begin(), closing.end());
    added += area;
    ++r.closed;
  }
  int nme0 = 0, nmv0 = 0, nme1 = 0, nmv1 = 0;
  CountNonManifold(input, &nme0, &nmv0);
  CountNonManifold(m, &nme1, &nmv1);
  if (nme1 > nme0 || nmv1 > nmv0) {
    r.closed = 0;
    r.refused = "closing them would make " + std::to_string(nme1 - nme0) + " edges and " +
                std::to_string(nmv1 - nmv0) + " vertices non-manifold";
    return r;
  }
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
