#pragma once
/// \file loop_vcg.h
/// vcg-mesh entry points of the Loop surrogate toolkit (for the MeshLab filters "Loop
/// Surrogate: Refine Surface / Snap Points / Curvature"). Each validates the input layer (see
/// ImportTriangles and LoopSurface), leaves it untouched on error and returns the error string.
#include <map>
#include <set>
#include <string>
#include <vector>

#include <vcg/complex/complex.h>
#include <wrap/callback.h>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/loop/loop_surface.h"
#include "vcg_ext/loop/loop_tools.h"

namespace vcgext {

/// Statistics of the vcg entry points.
struct LoopVcgReport {
  std::string error;
  int hardEdges = 0, hardVertices = 0, irregularFaces = 0;
  LoopInterpolateResult interp;  ///< filled when interpolation was requested
  LoopRefineResult refine;       ///< mesh arrays cleared after copying (stats kept)
  std::vector<double> distances; ///< snap: per moved vertex
  double maxDistance = 0, meanDistance = 0;
  int snapNotConverged = 0;
  std::vector<std::string> notes, warnings;  ///< repairs of the working copy (input_prep.h)
};

/// The working copy of a control-net layer (input_prep.h), its notes kept in `rep`.
template <class MeshType>
bool LoopWorkingCopy(const MeshType& m, WorkingCopy& w, LoopVcgReport& rep) {
  w = PrepareWorkingCopy(m);
  rep.error = w.error;
  rep.notes = w.notes;
  rep.warnings = w.warnings;
  return w.error.empty();
}

/// A warning in `rep` when the surface `s` was built with a shallower cache than `sp` asked for
/// (LoopSurfaceParams::maxMemoryMb): the results are the same, the evaluations slower.
inline void WarnIfCacheLowered(const LoopSurface& s, const LoopSurfaceParams& sp, LoopVcgReport& rep) {
  const int asked = RequestedCacheDepth(sp);
  if (!s.Ok() || s.CacheDepth() >= asked) return;
  rep.warnings.push_back("the control net is too large for the memory available at cache depth " + std::to_string(asked) +
                         ": its surface caches " + std::to_string(s.CacheDepth()) +
                         " levels, so evaluations are slower (bunny00 refined to 400k triangles at depth 0: about 8 "
                         "times as long); decimating the mesh first makes it faster");
}

/// `sp` with its extra hard edges (given on the layer's live vertices) moved onto the working
/// copy's vertices; edges at vertices the working copy left out are dropped. At a vertex the
/// working copy split (WorkingCopy::splitVertices) the edge goes to the copy whose sheet has it,
/// and an edge whose triangles were separated (WorkingCopy::separatedEdges) to every copy of it.
inline LoopSurfaceParams OnWorkingCopy(const LoopSurfaceParams& sp, const WorkingCopy& w) {
  LoopSurfaceParams p = sp;
  p.extraHardEdges.clear();
  // the split's copies of each layer vertex, beyond the one liveToMesh names, and the mesh's edges
  std::map<int, std::vector<int>> copies;
  for (int m = 0; m < int(w.meshToLive.size()); ++m)
    if (w.liveToMesh[size_t(w.meshToLive[size_t(m)])] != m) copies[w.meshToLive[size_t(m)]].push_back(m);
  std::set<std::pair<int, int>> edges;
  if (!copies.empty())
    for (const Tri& f : w.mesh.F)
      for (int k = 0; k < 3; ++k) edges.insert(std::minmax(f[k], f[(k + 1) % 3]));
  auto candidates = [&](int live) {
    std::vector<int> c{w.liveToMesh[size_t(live)]};
    const auto it = copies.find(live);
    if (it != copies.end()) c.insert(c.end(), it->second.begin(), it->second.end());
    return c;
  };
  for (const auto& [a, b] : sp.extraHardEdges) {
    const int n = int(w.liveToMesh.size());
    if (a < 0 || b < 0 || a >= n || b >= n || w.liveToMesh[a] < 0 || w.liveToMesh[b] < 0) continue;
    if (!copies.count(a) && !copies.count(b)) {
      p.extraHardEdges.push_back({w.liveToMesh[a], w.liveToMesh[b]});
      continue;
    }
    const size_t before = p.extraHardEdges.size();
    for (int ca : candidates(a))
      for (int cb : candidates(b))
        if (edges.count(std::minmax(ca, cb))) p.extraHardEdges.push_back({ca, cb});
    if (p.extraHardEdges.size() == before) p.extraHardEdges.push_back({w.liveToMesh[a], w.liveToMesh[b]});
  }
  return p;
}

/// Refine Surface: builds the Loop surface of `in` (optionally made interpolating, §3.3) and
/// writes the refined triangulation (§4) into `out` (cleared first). Per-vertex float
/// attributes "LoopFace", "LoopV", "LoopW" hold the parameters of each output vertex.
template <class MeshType>
LoopVcgReport LoopRefineMesh(const MeshType& in, MeshType& out, const LoopSurfaceParams& sp, bool interpolate,
                             const LoopRefineParams& rp, vcg::CallBackPos* cb = nullptr) {
  LoopVcgReport rep;
  WorkingCopy w;
  if (!LoopWorkingCopy(in, w, rep)) return rep;
  TriData& d = w.mesh;
  LoopSurfaceParams p = OnWorkingCopy(sp, w);
  if (interpolate) {
    LoopInterpolateParams ip;
    ip.surface = p;
    rep.interp = InterpolateLoopNet(d, ip);
    if (!rep.interp.error.empty()) { rep.error = rep.interp.error; return rep; }
    LoopSurface s0(d, p);
    p.creaseAngleDeg = 0;
    p.extraHardEdges = HardEdgeList(s0);
    d.V = rep.interp.X;
  }
  LoopSurface s(d, p);
  if (!s.Ok()) { rep.error = s.Error(); return rep; }
  WarnIfCacheLowered(s, p, rep);
  rep.hardEdges = s.NumHardEdges();
  rep.hardVertices = s.NumCornerVertices();
  rep.irregularFaces = s.NumIrregularFaces();
  rep.refine = RefineLoopSurface(s, rp, cb);
  if (!rep.refine.error.empty()) { rep.error = rep.refine.error; return rep; }
  out.Clear();
  const auto& R = rep.refine.mesh;
  auto vi = vcg::tri::Allocator<MeshType>::AddVertices(out, R.V.size());
  for (size_t i = 0; i < R.V.size(); ++i, ++vi) vi->P() = typename MeshType::CoordType(R.V[i][0], R.V[i][1], R.V[i][2]);
  auto fi = vcg::tri::Allocator<MeshType>::AddFaces(out, R.F.size());
  for (size_t f = 0; f < R.F.size(); ++f, ++fi)
    for (int k = 0; k < 3; ++k) fi->V(k) = &out.vert[R.F[f][k]];
  auto hf = vcg::tri::Allocator<MeshType>::template GetPerVertexAttribute<float>(out, "LoopFace");
  auto hv = vcg::tri::Allocator<MeshType>::template GetPerVertexAttribute<float>(out, "LoopV");
  auto hw = vcg::tri::Allocator<MeshType>::template GetPerVertexAttribute<float>(out, "LoopW");
  for (size_t i = 0; i < R.V.size(); ++i) {
    hf[i] = float(rep.refine.paramFace[i]);
    hv[i] = float(rep.refine.paramV[i]);
    hw[i] = float(rep.refine.paramW[i]);
  }
  rep.refine.mesh = TriData();
  return rep;
}

/// Snap Points: moves every live vertex of `points` onto the Loop surface of `netMesh`
/// (closest point, §2.1) and reports the distances (absolute units).
template <class MeshType>
LoopVcgReport LoopSnapVertices(MeshType& points, const MeshType& netMesh, const LoopSurfaceParams& sp) {
  LoopVcgReport rep;
  WorkingCopy w;
  if (!LoopWorkingCopy(netMesh, w, rep)) return rep;
  const TriData& d = w.mesh;
  LoopSurface s(d, OnWorkingCopy(sp, w));
  if (!s.Ok()) { rep.error = s.Error(); return rep; }
  WarnIfCacheLowered(s, sp, rep);
  EmbreeScene scene(d);
  if (!scene.Ok()) { rep.error = scene.Error(); return rep; }
  std::vector<Vec3> q;
  for (const auto& v : points.vert)
    if (!v.IsD()) q.emplace_back(v.cP()[0], v.cP()[1], v.cP()[2]);
  for (const auto& x : q)
    if (!x.allFinite()) { rep.error = "the point layer has NaN or infinite coordinates"; return rep; }
  std::vector<LoopSnapResult> r(q.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (int i = 0; i < int(q.size()); ++i) r[i] = SnapToLoopSurface(s, q[i], &scene);
  size_t i = 0;
  double sum = 0;
  for (auto& v : points.vert) {
    if (v.IsD()) continue;
    v.P() = typename MeshType::CoordType(r[i].point[0], r[i].point[1], r[i].point[2]);
    rep.distances.push_back(r[i].distance);
    rep.maxDistance = std::max(rep.maxDistance, r[i].distance);
    sum += r[i].distance;
    rep.snapNotConverged += r[i].converged ? 0 : 1;
    ++i;
  }
  rep.meanDistance = q.empty() ? 0 : sum / q.size();
  return rep;
}

/// Curvature: per-vertex quality Q() = the chosen curvature of the limit surface at each
/// vertex's limit point (see LoopVertexCurvature for extraordinary / crease vertices).
template <class MeshType>
LoopVcgReport LoopCurvatureToQuality(MeshType& m, const LoopSurfaceParams& sp, LoopCurvatureKind kind) {
  LoopVcgReport rep;
  WorkingCopy w;
  if (!LoopWorkingCopy(m, w, rep)) return rep;
  LoopSurface s(w.mesh, OnWorkingCopy(sp, w));
  if (!s.Ok()) { rep.error = s.Error(); return rep; }
  WarnIfCacheLowered(s, sp, rep);
  rep.hardEdges = s.NumHardEdges();
  rep.hardVertices = s.NumCornerVertices();
  // vertices in no face have no limit point: 0
  std::vector<double> k = ToLiveVertices(w, LoopVertexCurvature(s, kind), 0.0);
  size_t i = 0;
  for (auto& v : m.vert) {
    if (v.IsD()) continue;
    v.Q() = typename MeshType::ScalarType(k[i++]);
  }
  return rep;
}

}  // namespace vcgext
