#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/edge_faces.h"
#include "vcg_ext/core/seams.h"
#include "vcg_ext/core/staircase.h"
#include "vcg_ext/core/union_find.h"
#include "vcg_ext/core/vertex_grid.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <map>
#include <numeric>
#include <unordered_map>

namespace vcgext {
namespace {

// 1. exact duplicates: every vertex mapped to the first vertex with the same coordinates.
std::vector<int> MergeExactDuplicates(const std::vector<Vec3>& V, int* merged) {
  std::vector<int> order(V.size()), rep(V.size());
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    for (int k = 0; k < 3; ++k)
      if (V[a][k] != V[b][k]) return V[a][k] < V[b][k];
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  *merged = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    const int v = order[i];
    if (i > 0 && V[v] == V[order[i - 1]]) {
      rep[v] = rep[order[i - 1]];
      ++*merged;
    } else {
      rep[v] = v;
    }
  }
  return rep;
}

// 1b. An unwelded export whose coordinates were rounded per face: a triangle soup that the exact
// merge left apart (more than kSoupVerticesPerFace distinct vertices per face, where a welded
// surface has about 0.5). Each referenced vertex within kWeldTolerance of the diagonal of one kept
// before it (the first such, by index; a grid of that cell size) is merged into it, and the weld is
// kept when it leaves at most one vertex per face; separate pieces on purpose (particles, specks)
// stay as they are. `rep` maps onto the kept vertices; returns how many were welded.
constexpr double kSoupVerticesPerFace = 1.5, kWeldTolerance = 1e-6;
int WeldRoundedSoup(const std::vector<Vec3>& V, const std::vector<Tri>& F, std::vector<int>& rep) {
  std::vector<char> referenced(V.size(), 0);
  long distinct = 0;
  for (const Tri& f : F)
    for (int v : f)
      if (!referenced[size_t(rep[size_t(v)])]) referenced[size_t(rep[size_t(v)])] = 1, ++distinct;
  const double eps = kWeldTolerance * BBoxDiagonal(V);
  if (!(double(distinct) > kSoupVerticesPerFace * double(F.size())) || !(eps > 0) || !std::isfinite(eps)) return 0;
  std::vector<int> verts;
  for (size_t v = 0; v < V.size(); ++v)
    if (referenced[v]) verts.push_back(int(v));
  int welded = 0;
  const std::vector<int> weld = WeldWithin(V, verts, eps, [](int, int) { return true; }, &welded);
  if (long(verts.size()) - welded > long(F.size())) return 0;  // more than one vertex per face kept
  for (int& r : rep) r = weld[size_t(r)];
  return welded;
}

// 2. degenerate and repeated faces dropped.
std::vector<Tri> UniqueFaces(const std::vector<Tri>& F, const std::vector<int>& rep, WorkingCopy& w) {
  std::vector<Tri> out;
  out.reserve(F.size());
  std::vector<std::pair<std::array<int, 3>, int>> sorted;
  for (const Tri& f0 : F) {
    Tri f{rep[f0[0]], rep[f0[1]], rep[f0[2]]};
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) { ++w.degenerateFaces; continue; }
    std::array<int, 3> s = f;
    std::sort(s.begin(), s.end());
    sorted.push_back({s, int(out.size())});
    out.push_back(f);
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<char> drop(out.size(), 0);
  for (size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i].first == sorted[i - 1].first) { drop[sorted[i].second] = 1; ++w.duplicateFaces; }
  std::vector<Tri> kept;
  kept.reserve(out.size());
  for (size_t i = 0; i < out.size(); ++i)
    if (!drop[i]) kept.push_back(out[i]);
  return kept;
}

int NonManifoldEdges(const EdgeFaces& e) {
  int n = 0;
  for (size_t id = 0; id + 1 < e.offs.size(); ++id) n += e.offs[id + 1] - e.offs[id] > 2;
  return n;
}

// The face side of each edge of one face.
std::vector<int> BoundarySides(const EdgeFaces& e) {
  std::vector<int> sides;
  for (size_t id = 0; id + 1 < e.offs.size(); ++id)
    if (e.offs[id + 1] - e.offs[id] == 1) sides.push_back(e.idx[size_t(e.offs[id])]);
  return sides;
}

// Two faces on the same three vertices (either orientation): welding a seam can make them (a
// sliver on each side of it; the fuzzer found one).
bool HasRepeatedFaces(const std::vector<Tri>& F) {
  std::vector<std::array<int, 3>> sorted(F.begin(), F.end());
  for (auto& f : sorted) std::sort(f.begin(), f.end());
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

// 2b. Seams closed (seams.h): near-coincident boundary vertices welded and T-junctions closed
// within a millionth of the diagonal, or the float spacing of the coordinates if coarser (a vertex
// computed on an edge is off it by rounding). Kept when it joins edges (fewer boundary edges),
// makes no more of three or more triangles and repeats no face; F, e and rep replaced.
void CloseSeams(const std::vector<Vec3>& V, std::vector<Tri>& F, EdgeFaces& e, std::vector<int>& rep, WorkingCopy& w) {
  const std::vector<int> boundary = BoundarySides(e);
  if (boundary.empty()) return;
  const double tol = std::max(kWeldTolerance * BBoxDiagonal(V), std::ldexp(LargestCoordinate(V), -23));
  std::vector<int> into;
  const int welded = WeldSeamVertices(V, F, boundary, tol, into);
  std::vector<Tri> closed = F;
  for (Tri& f : closed)
    for (int& v : f) v = into[size_t(v)];
  EdgeFaces ce = welded ? BuildEdgeFaces(closed) : e;
  const int inserted = CloseTJunctions(V, closed, welded ? BoundarySides(ce) : boundary, tol);
  if (welded == 0 && inserted == 0) return;
  if (inserted) ce = BuildEdgeFaces(closed);
  if (BoundarySides(ce).size() >= boundary.size() || NonManifoldEdges(ce) > NonManifoldEdges(e) ||
      HasRepeatedFaces(closed))
    return;
  F.swap(closed);
  e = std::move(ce);
  for (int& r : rep) r = into[size_t(r)];
  w.seamVertices = welded;
  w.closedTJunctions = inserted;
}

// 2c. Cracks: boundary vertices still near another boundary's after the seams were closed (a
// crack or an unwelded seam wider than the weld's millionth of the diagonal) are not welded (how
// far apart two boundaries may lie and still be one surface is the user's call) but warned about
// from kCrackVertices on: closer than kCrackEdgeShare of their shortest boundary edges and of the
// median one, sharing no edge (NearBoundaryVertices). The warning gives MeshLab's weld with a
// merging distance of 1.5 x the widest such gap, at most that tolerance.
constexpr int kCrackVertices = 10;
constexpr double kCrackEdgeShare = 0.1;
void WarnOfCracks(const std::vector<Vec3>& V, const std::vector<Tri>& F, const EdgeFaces& e, WorkingCopy& w) {
  double reach = 0, widest = 0;
  const int near = NearBoundaryVertices(V, F, BoundarySides(e), kCrackEdgeShare, reach, widest);
  if (near < kCrackVertices) return;
  const double diag = BBoxDiagonal(V), threshold = std::min(1.5 * widest, reach);
  char buf[700];
  std::snprintf(buf, sizeof buf,
                "%d boundary vertices lie near another boundary's (up to %.3g %% of the diagonal apart, sharing no "
                "edge): cracks or an unwelded seam, wider than the millionth of the diagonal welded here. Each stays "
                "open, a hole in every surface fitted to it (more patches, area around it left unreached). If they "
                "are one surface, weld them first: Filters > Cleaning and Repairing > Merge Close Vertices with a "
                "merging distance of %.4g (%.3g %% of the diagonal; PyMeshLab: meshing_merge_close_vertices)",
                near, 100 * widest / diag, threshold, 100 * threshold / diag);
  w.warnings.push_back(buf);
  w.crackVertices = near;
}

// 3a. Per face side (face * 3 + k), the side joined to it across its edge, -1 for none: the other
// side of an edge of two faces; on an edge of three or more (a fin, two closed parts sharing an
// edge), with `pairFins`, the two sides that continue each other most smoothly — a pair running
// the edge in opposite directions (consistently oriented) with the largest dot product of the
// faces' normals, or when the edge has no such pair the one that is after flipping a face — and
// none for the rest. A sheet with a flap along a chain of its edges keeps the sheet joined across
// the chain (the flap comes off); without the pairing the sheet would be slit along it.
std::vector<int> JoinedSides(const std::vector<Tri>& F, const std::vector<Vec3>& V, const EdgeFaces& e, bool pairFins) {
  std::vector<int> join(e.sideEdge.size(), -1);
  auto normal = [&](int f) {
    const Vec3 n = (V[F[f][1]] - V[F[f][0]]).cross(V[F[f][2]] - V[F[f][0]]);
    return n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
  };
  for (size_t id = 0; id + 1 < e.offs.size(); ++id) {
    const int b = e.offs[id], n = e.offs[id + 1] - b;
    if (n < 2 || (n > 2 && !pairFins)) continue;
    int s0 = e.idx[b], s1 = e.idx[b + 1];
    if (n > 2) {
      double best = -3;
      bool bestOpposite = false;
      for (int i = b; i < b + n; ++i)
        for (int j = i + 1; j < b + n; ++j) {
          const int si = e.idx[i], sj = e.idx[j];
          const bool opposite = F[si / 3][si % 3] != F[sj / 3][sj % 3];  // different start vertices
          const double d = normal(si / 3).dot(normal(sj / 3)), score = opposite ? d : -d;
          if ((opposite && !bestOpposite) || (opposite == bestOpposite && score > best)) {
            best = score;
            bestOpposite = opposite;
            s0 = si;
            s1 = sj;
          }
        }
    }
    join[size_t(s0)] = s1;
    join[size_t(s1)] = s0;
  }
  return join;
}

// 3b. vertices whose incident faces form more than one fan (faces joined across an edge, `join`,
// are in one fan at both its ends). With `copyOf`, each fan but the one holding the vertex's first
// face gets its own copy of the vertex (numbered nV, nV + 1, ... in the order made; copyOf lists
// the original of each) and its faces are rewired to it: a bow-tie becomes two sheets that touch
// without sharing a vertex (MeshLab's Repair non Manifold Vertices does the same), and a face left
// unjoined on an edge of three or more faces comes off it with its fans.
int NonManifoldVertices(std::vector<Tri>& F, const std::vector<int>& join, int nV, std::vector<int>* copyOf) {
  const Adjacency vf = VertexFaceAdjacency(F, nV);
  UnionFind local;
  std::vector<int> copyOfRoot;
  int bad = 0;
  for (int v = 0; v < nV; ++v) {
    const int* fs = vf.Begin(v);
    const int nf = vf.Count(v);
    if (nf < 2) continue;
    local.Reset(nf);
    auto slot = [&](int f) { return int(std::find(fs, fs + nf, f) - fs); };
    for (int i = 0; i < nf; ++i) {
      const int f = fs[i];
      for (int k = 0; k < 3; ++k) {
        if (F[f][k] != v && F[f][(k + 1) % 3] != v) continue;
        const int other = join[size_t(f * 3 + k)];
        if (other >= 0) local.Unite(slot(other / 3), i);
      }
    }
    int roots = 0;
    for (int i = 0; i < nf; ++i) roots += local.Find(i) == i;
    bad += roots > 1;
    if (roots < 2 || !copyOf) continue;
    // the fan of the first face keeps v; every other fan's root gets a copy
    copyOfRoot.assign(size_t(nf), -1);
    const int keep = local.Find(0);
    for (int i = 0; i < nf; ++i) {
      const int root = local.Find(i);
      if (root == keep) continue;
      if (copyOfRoot[root] < 0) {
        copyOfRoot[root] = nV + int(copyOf->size());
        copyOf->push_back(v);
      }
      for (int& c : F[fs[i]])
        if (c == v) c = copyOfRoot[root];
    }
  }
  return bad;
}

std::string Plural(int n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Coordinates that float rounding has moved by more than this share of the bbox diagonal: the
// model's shape is gone (far1e7.off of the bad-input corpus, a unit sphere at x = 1e7, is a blob of
// 1-unit steps that the pipeline turned into 4 728 patches in 314 s): an error, not a warning.
constexpr double kLostShapeQuantum = 1e-2;

bool AllFloats(const std::vector<Vec3>& V) {
  for (const Vec3& p : V)
    for (int k = 0; k < 3; ++k)
      if (RoundedToFloat(p[k]) != p[k]) return false;
  return true;
}

// A warning when single-precision storage rounds the positions by more than 1e-5 of the
// diagonal; an error when it rounds them by more than kLostShapeQuantum and they are in fact
// floats (MeshLab 2020.09's layers; a double layer keeps its shape).
void CheckPrecision(const std::vector<Vec3>& V, WorkingCopy& w) {
  const double far = LargestCoordinate(V);
  const double diag = BBoxDiagonal(V);
  const double quantum = far * std::ldexp(1.0, -23);  // single-precision spacing at |x| = far
  if (!(diag > 0) || quantum <= 1e-5 * diag) return;
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "coordinates are far from the origin (up to %.3g, %.3g times the model's size): MeshLab stores "
                "single-precision floats, which round positions to steps of %.3g (%.2g %% of the bounding-box "
                "diagonal)",
                far, far / diag, quantum, 100 * quantum / diag);
  if (quantum > kLostShapeQuantum * diag && AllFloats(V))
    w.error = std::string(buf) + ": the model's shape is lost; move it near the origin in the program that wrote "
                                 "the file (MeshLab reads coordinates as floats)";
  else
    w.warnings.push_back(std::string(buf) + "; move the model to the origin first (Filters > Normals, Curvatures and "
                                            "Orientation > Transform: Translate, Center, set Origin)");
}

}  // namespace

namespace {
WorkingCopy PrepareWorkingCopyImpl(const TriData& raw, bool merge);
}  // namespace

namespace {
// The latest working copy of a large layer: the three pipeline filters each prepare the same
// layer (bunny00 x16, 1.2 M triangles: ~0.5 s each). Identified by the exact contents of `raw`
// (a 64-bit hash of its arrays, plus their sizes); one copy is kept.
constexpr size_t kMemoMinFaces = 200000;
struct PreparedMemo {
  std::mutex lock;
  std::uint64_t key = 0;
  size_t nv = 0, nf = 0;
  WorkingCopy w;
};
PreparedMemo& Prepared() {
  static PreparedMemo memo;
  return memo;
}
std::uint64_t HashArrays(const TriData& raw) {
  std::uint64_t h = 1469598103934665603ull;
  auto eat = [&](const void* data, size_t bytes) {
    const unsigned char* b = static_cast<const unsigned char*>(data);
    size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      std::uint64_t x;
      std::memcpy(&x, b + i, 8);
      h = (h ^ x) * 1099511628211ull;
      h ^= h >> 29;
    }
    for (; i < bytes; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  eat(raw.V.data(), raw.V.size() * sizeof(Vec3));
  eat(raw.F.data(), raw.F.size() * sizeof(Tri));
  return h;
}
WorkingCopy PrepareUncached(const TriData& raw);
}  // namespace

namespace {
std::atomic<CoordinatePrecision>& Precision() {
  static std::atomic<CoordinatePrecision> p{CoordinatePrecision::AsGiven};
  return p;
}
}  // namespace

void SetInputCoordinatePrecision(CoordinatePrecision p) { Precision() = p; }
CoordinatePrecision InputCoordinatePrecision() { return Precision(); }

bool RoundCoordinatesToFloat(std::vector<Vec3>& V) {
  if (V.empty()) return false;
  const double maxAbs = LargestCoordinate(V);
  // float's spacing near maxAbs is at most 2^-23 maxAbs: rounding moves a value by half of it
  if (!(std::ldexp(maxAbs, -24) <= 1e-6 * BBoxDiagonal(V))) return false;
  for (Vec3& v : V)
    for (int k = 0; k < 3; ++k) v[k] = RoundedToFloat(v[k]);
  return true;
}

void ApplyInputCoordinatePrecision(std::vector<Vec3>& V) {
  if (InputCoordinatePrecision() == CoordinatePrecision::Float) RoundCoordinatesToFloat(V);
}

WorkingCopy PrepareWorkingCopy(const TriData& raw) {
  if (raw.F.size() < kMemoMinFaces) return PrepareUncached(raw);
  const std::uint64_t key = HashArrays(raw);
  PreparedMemo& memo = Prepared();
  {
    std::lock_guard<std::mutex> g(memo.lock);
    if (memo.key == key && memo.nv == raw.V.size() && memo.nf == raw.F.size()) return memo.w;
  }
  WorkingCopy w = PrepareUncached(raw);
  std::lock_guard<std::mutex> g(memo.lock);
  memo.key = key;
  memo.nv = raw.V.size();
  memo.nf = raw.F.size();
  memo.w = w;
  return w;
}

namespace {
WorkingCopy PrepareUncached(const TriData& raw) {
  WorkingCopy w = PrepareWorkingCopyImpl(raw, true);
  if ((w.mergedVertices > 0 || w.weldedVertices > 0) && (w.nonManifoldEdges > 0 || w.nonManifoldVertices > 0)) {
    // Coincident vertices can be distinct on purpose (a scan touching itself at a point, the
    // two sides of a crack): when merging them is what makes the surface non-manifold, they
    // stay apart — unless apart the surface falls into more pieces (an STL soup of a mesh with
    // one non-manifold vertex would be kept as a soup of separate triangles).
    WorkingCopy apart = PrepareWorkingCopyImpl(raw, false);
    if (apart.nonManifoldEdges == 0 && apart.nonManifoldVertices == 0 && apart.error.empty() &&
        apart.components <= w.components) {
      apart.notes.insert(apart.notes.begin(), "kept " + std::to_string(w.mergedVertices + w.weldedVertices) +
                                                  " coincident vertices apart (merging them would make the surface non-manifold)");
      w = std::move(apart);
    }
  }
  // coordinates rounded by float precision can be the cause of the error (a far-off model whose
  // vertices collapse onto each other): say so with it
  if (!w.error.empty() && !w.warnings.empty()) w.error += " (" + w.warnings.front() + ")";
  if (w.error.empty()) {  // rounded coordinates, voxel faces (staircase.h)
    const Staircase stairs = FindStaircase(raw, w.mesh);
    if (const std::string warning = StaircaseWarning(stairs); !warning.empty()) w.warnings.push_back(warning);
    w.staircaseStepEdges = stairs.StepEdges();
  }
  return w;
}
}  // namespace

namespace {
// 3c. The split (3a, 3b), F and e replaced by the split's: with the faces on each edge of three or
// more paired smoothly, and when that leaves such an edge (a closed part with a flap continuing one
// of its faces: the flap and both of the part's faces stay in one fan at both ends), with every
// face taken off those edges instead, which always leaves at most two triangles on an edge: around
// a vertex, faces joined only across edges of two form chains, and a chain has two ends, so at most
// two of an edge's triangles share a fan at each of its ends. MeshLab's Repair non Manifold Edges
// deletes faces; this keeps them all. (False, with an internal error, should that ever fail.)
bool SplitNonManifold(const std::vector<Vec3>& V, int n, std::vector<Tri>& F, EdgeFaces& e, std::vector<int>& copyOf,
                      WorkingCopy& w) {
  w.nonManifoldEdges = NonManifoldEdges(e);
  const std::vector<Tri> given = w.nonManifoldEdges ? F : std::vector<Tri>();
  for (int attempt = 0; attempt < (w.nonManifoldEdges ? 2 : 1); ++attempt) {
    if (attempt > 0) {
      F = given;
      e = BuildEdgeFaces(F);
      copyOf.clear();
    }
    w.nonManifoldVertices = NonManifoldVertices(F, JoinedSides(F, V, e, attempt == 0), n, &copyOf);
    if (!copyOf.empty()) e = BuildEdgeFaces(F);  // the split renamed edges at the split vertices
    if (NonManifoldEdges(e) == 0) {
      w.splitVertices = w.nonManifoldVertices;
      w.separatedEdges = w.nonManifoldEdges;
      return true;
    }
  }
  w.error = "internal error: separating the triangles on " +
            Plural(w.nonManifoldEdges, "edge", "edges") + " shared by more than two left such an edge; repair it with "
            "Filters > Cleaning and Repairing > Repair non Manifold Edges (and please report the mesh)";
  return false;
}

// One log line per repair the working copy made.
void AddRepairNotes(WorkingCopy& w) {
  if (w.mergedVertices)
    w.notes.push_back("merged " + Plural(w.mergedVertices, "duplicate vertex", "duplicate vertices") +
                      " (same coordinates: an unwelded mesh or STL soup)");
  if (w.weldedVertices)
    w.notes.push_back("welded " + Plural(w.weldedVertices, "vertex", "vertices") +
                      " lying within a millionth of the diagonal of another (an unwelded export whose coordinates "
                      "were rounded face by face: apart, every triangle was a piece of its own)");
  if (w.seamVertices)
    w.notes.push_back("welded " + Plural(w.seamVertices, "boundary vertex", "boundary vertices") +
                      " lying within a millionth of the diagonal of another boundary's (a seam between separately "
                      "meshed parts, each with its own copies of the seam's vertices)");
  if (w.closedTJunctions)
    w.notes.push_back("closed " + Plural(w.closedTJunctions, "T-junction", "T-junctions") +
                      " (a vertex lying on another triangle's boundary edge: that triangle is split at it, so that "
                      "separately meshed parts of the surface are joined, not left as open sheets)");
  if (w.degenerateFaces)
    w.notes.push_back("ignored " + Plural(w.degenerateFaces, "degenerate face", "degenerate faces") +
                      " (a repeated vertex)");
  if (w.duplicateFaces) w.notes.push_back("ignored " + Plural(w.duplicateFaces, "repeated face", "repeated faces"));
  if (w.unreferencedVertices)
    w.notes.push_back("ignored " + Plural(w.unreferencedVertices, "unreferenced vertex", "unreferenced vertices") +
                      " (in no face)");
  if (w.separatedEdges)
    w.notes.push_back("separated the triangles on " + Plural(w.separatedEdges, "edge", "edges") +
                      " shared by more than two: a triangle that does not continue the surface across such an edge "
                      "gets its own copies of the edge's vertices (a fin or flap becomes a piece of its own; no "
                      "triangle is deleted, unlike Filters > Cleaning and Repairing > Repair non Manifold Edges)");
  if (w.splitVertices)
    w.notes.push_back("split " + Plural(w.splitVertices, "vertex", "vertices") +
                      " where separate pieces of surface touch (one copy per piece, as Filters > Cleaning and "
                      "Repairing > Repair non Manifold Vertices does; the layer's vertex shows the first piece's value)");
  if (w.flippedFaces)
    w.notes.push_back("re-oriented " + Plural(w.flippedFaces, "face", "faces") +
                      " so that every component is consistently oriented");
}

WorkingCopy PrepareWorkingCopyImpl(const TriData& raw, bool merge) {
  WorkingCopy w;
  const int n = int(raw.V.size());
  CheckPrecision(raw.V, w);
  if (!w.error.empty()) return w;
  std::vector<int> rep(n);
  if (merge) {
    rep = MergeExactDuplicates(raw.V, &w.mergedVertices);
    w.weldedVertices = WeldRoundedSoup(raw.V, raw.F, rep);
  } else {
    std::iota(rep.begin(), rep.end(), 0);
  }
  std::vector<Tri> F = UniqueFaces(raw.F, rep, w);
  if (F.empty()) {
    w.error = "all " + Plural(int(raw.F.size()), "face is", "faces are") +
              " degenerate (zero length edges: each repeats a vertex" +
              std::string(w.mergedVertices ? " once coincident vertices are merged" : "") + ")";
    return w;
  }
  EdgeFaces e = BuildEdgeFaces(F);
  CloseSeams(raw.V, F, e, rep, w);
  WarnOfCracks(raw.V, F, e, w);
  std::vector<int> copyOf;  // per vertex made by the split (indices n, n + 1, ...): its original
  if (!SplitNonManifold(raw.V, n, F, e, copyOf, w)) return w;
  w.flippedFaces = OrientComponents(F, e, &w.components, &w.nonOrientableComponents);
  if (w.nonOrientableComponents) {
    w.error = "the surface is not orientable (" + Plural(w.nonOrientableComponents, "component", "components") +
              " like a Möbius strip: no consistent inside and outside), so it has no consistent normals; "
              "a subdivision surface cannot follow it";
    return w;
  }
  // 5. compact: referenced vertices only, in the layer's order, then the split's copies
  const int nAll = n + int(copyOf.size());
  std::vector<int> newIndex(size_t(nAll), -1);
  for (const Tri& f : F)
    for (int v : f) newIndex[v] = 0;
  for (int v = 0; v < nAll; ++v)
    if (newIndex[v] == 0) {
      const int live = v < n ? v : copyOf[size_t(v - n)];
      newIndex[v] = int(w.mesh.V.size());
      w.mesh.V.push_back(raw.V[live]);
      w.meshToLive.push_back(live);
    }
  w.mesh.F.reserve(F.size());
  for (const Tri& f : F) w.mesh.F.push_back({newIndex[f[0]], newIndex[f[1]], newIndex[f[2]]});
  w.liveToMesh.resize(n);
  for (int v = 0; v < n; ++v) {
    w.liveToMesh[v] = newIndex[rep[v]];
    w.unreferencedVertices += w.liveToMesh[v] < 0;
  }
  AddRepairNotes(w);
  return w;
}
}  // namespace

bool RemapQuadsToWorkingCopy(const WorkingCopy& w, std::vector<Quad>& quads) {
  if (w.splitVertices > 0 || w.closedTJunctions > 0) return false;
  // Each quad side must run as a side of one of the quad's own triangles in the working copy (the
  // triangle on that side, the same way round, has its third corner among the quad's): the quads
  // then bound the working copy's faces as it orients them (a layer whose faces the working copy
  // turned is usable when the quads were read oriented the same way, ImportQuads' `flipped`). The
  // working copy is manifold and oriented: each directed side belongs to one triangle at most.
  std::unordered_map<uint64_t, int> third;
  third.reserve(3 * w.mesh.F.size());
  auto side = [](int a, int b) { return uint64_t(uint32_t(a)) << 32 | uint32_t(b); };
  for (const Tri& f : w.mesh.F)
    for (int k = 0; k < 3; ++k) third[side(f[k], f[(k + 1) % 3])] = f[(k + 2) % 3];
  for (Quad& q : quads) {
    for (int& v : q) {
      if (v < 0 || v >= int(w.liveToMesh.size()) || w.liveToMesh[v] < 0) return false;
      v = w.liveToMesh[v];
    }
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b)
        if (q[a] == q[b]) return false;
      const auto t = third.find(side(q[a], q[(a + 1) % 4]));
      if (t == third.end() || (t->second != q[(a + 2) % 4] && t->second != q[(a + 3) % 4])) return false;
    }
  }
  return true;
}

}  // namespace vcgext
