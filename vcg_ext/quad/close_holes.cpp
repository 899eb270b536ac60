/// \file close_holes.cpp
/// Small holes closed by vcglib's ear cutting (close_holes.h).
#include "vcg_ext/quad/close_holes.h"

#include <vcg/complex/algorithms/hole.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/complex.h>

#include <algorithm>
#include <array>
#include <vector>

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

void ToVcg(const TriData& m, HMesh& h) {
  auto vi = vcg::tri::Allocator<HMesh>::AddVertices(h, m.V.size());
  for (const Vec3& p : m.V) (vi++)->P() = vcg::Point3d(p.x(), p.y(), p.z());
  auto fi = vcg::tri::Allocator<HMesh>::AddFaces(h, m.F.size());
  for (const Tri& f : m.F) {
    for (int c = 0; c < 3; ++c) fi->V(c) = &h.vert[size_t(f[c])];
    ++fi;
  }
  vcg::tri::UpdateTopology<HMesh>::FaceFace(h);
  vcg::tri::UpdateNormal<HMesh>::PerVertexNormalizedPerFaceNormalized(h);
}

double Area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

// The vertices of the boundary loop from `p`, in order.
std::vector<int> LoopVertices(const HMesh& h, const Hole::PosType& p) {
  std::vector<int> loop;
  Hole::PosType q = p;
  do {
    loop.push_back(int(q.v - &h.vert[0]));
    q.NextB();
  } while (q != p && loop.size() <= h.vert.size());
  return loop;
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

// The holes of `h` to close (indices into `holes`): not a piece's outline (kOutlineShare), and
// below the size rule; r.holes counts the holes.
std::vector<size_t> SmallLoops(const HMesh& h, const std::vector<Hole::Info>& holes, const std::vector<double>& pieceDiag,
                               double maxDiag, int maxEdges, CloseHolesResult& r) {
  std::vector<size_t> chosen;
  r.holes = 0;
  for (size_t k = 0; k < holes.size(); ++k) {
    const Hole::Info& i = holes[k];
    const double d = vcg::Distance(i.bb.min, i.bb.max);
    if (d >= kOutlineShare * pieceDiag[size_t(i.p.v - &h.vert[0])]) continue;  // the piece's outline
    ++r.holes;
    if (d < maxDiag || i.size <= maxEdges) chosen.push_back(k);
  }
  return chosen;
}

}  // namespace

CloseHolesResult CloseSmallHoles(const TriData& input, const CloseHolesParams& p) {
  CloseHolesResult r;
  r.mesh = input;
  if (!(p.maxDiagonalPercent > 0) || input.F.empty()) return r;
  const std::vector<double> pieceDiag = PieceDiagonals(input);
  const double maxDiag = p.maxDiagonalPercent / 100.0 * BBoxDiagonal(input.V);
  // a small hole through two copies of one point: the copies are joined again first (vcglib's
  // ear cutting closes a loop through a vertex twice; closed, that vertex is manifold again)
  TriData m = input;
  std::vector<int> into(m.V.size(), -1);
  {
    HMesh h;
    ToVcg(m, h);
    std::vector<Hole::Info> holes;
    Hole::GetInfo(h, false, holes);
    bool any = false;
    for (size_t k : SmallLoops(h, holes, pieceDiag, maxDiag, p.maxEdges, r))
      any = CopiesOnLoop(m.V, LoopVertices(h, holes[k].p), into) || any;
    if (any)
      for (Tri& f : m.F)
        for (int& v : f) v = into[size_t(v)] >= 0 ? into[size_t(v)] : v;
  }
  HMesh h;
  ToVcg(m, h);
  std::vector<Hole::Info> holes;
  Hole::GetInfo(h, false, holes);
  std::vector<HMesh::FacePointer*> update;  // FillHoleEar's added faces may move the vector
  for (Hole::Info& i : holes) update.push_back(&i.p.f);
  // each hole's closing triangles (a range at the end of h.face), kept unless one is degenerate
  // or the loop still passes two copies of a point
  double added = 0;
  for (size_t k : SmallLoops(h, holes, pieceDiag, maxDiag, p.maxEdges, r)) {
    std::vector<int> copies(m.V.size(), -1);
    if (CopiesOnLoop(m.V, LoopVertices(h, holes[k].p), copies)) {
      ++r.skipped;
      continue;
    }
    const size_t before = h.face.size();
    Hole::FillHoleEar<vcg::tri::MinimumWeightEar<HMesh>>(h, holes[k].p, update);
    std::vector<Tri> closing;
    double area = 0;
    for (size_t f = before; f < h.face.size(); ++f) {
      if (h.face[f].IsD()) continue;
      Tri t;
      for (int c = 0; c < 3; ++c) t[c] = int(h.face[f].V(c) - &h.vert[0]);
      const double a = Area(m.V[size_t(t[0])], m.V[size_t(t[1])], m.V[size_t(t[2])]);
      area = a > 0 && area >= 0 ? area + a : -1;
      closing.push_back(t);
    }
    if (area < 0 || closing.empty()) {
      ++r.skipped;
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
    r.closed = r.joinedVertices = 0;
    r.refused = "closing them would make " + std::to_string(nme1 - nme0) + " edges and " +
                std::to_string(nmv1 - nmv0) + " vertices non-manifold";
    return r;
  }
  r.closedAreaPct = 100.0 * added / std::max(TotalArea(input), 1e-300);
  // the joined copies leave the vertex array (vertexMap: old -> new index)
  for (int t : into) r.joinedVertices += t >= 0;
  if (r.joinedVertices > 0) {
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
