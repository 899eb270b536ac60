#include "vcg_ext/core/decimate.h"

// vcglib's quadric collapse (third-party) trips GCC 12's -Wmaybe-uninitialized on its optimal
// placement point (tri_edge_collapse_quadric.h: x is set by the quadric's Minimum()); its
// templates are instantiated in this file, so the warning is silenced here only.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/algorithms/local_optimization.h>
#include <vcg/complex/algorithms/local_optimization/tri_edge_collapse_quadric.h>
#include <vcg/complex/algorithms/isotropic_remeshing.h>
#include <vcg/complex/algorithms/refine.h>
#include <vcg/complex/complex.h>

namespace vcgext {
namespace {

// A mesh type with what the quadric collapse needs (VF adjacency, marks, a quadric per vertex).
class DVertex;
class DFace;
struct DUsedTypes
    : public vcg::UsedTypes<vcg::Use<DVertex>::AsVertexType, vcg::Use<DFace>::AsFaceType> {};
class DVertex : public vcg::Vertex<DUsedTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d, vcg::vertex::VFAdj,
                                   vcg::vertex::Mark, vcg::vertex::Qualityd, vcg::vertex::BitFlags> {
 public:
  vcg::math::Quadric<double>& Qd() { return q_; }

 private:
  vcg::math::Quadric<double> q_;
};
class DFace : public vcg::Face<DUsedTypes, vcg::face::VertexRef, vcg::face::Normal3d, vcg::face::VFAdj,
                               vcg::face::FFAdj, vcg::face::Mark, vcg::face::Qualityd, vcg::face::BitFlags> {};
// vcglib 2020.09's TriMesh never initialises its attribute counter `attrn` (only ClearAttributes
// does): the ids of the temporary attributes (the isotropic remeshing's SelectionStack) would
// start from stack garbage (valgrind). Set here.
class DMesh : public vcg::tri::TriMesh<std::vector<DVertex>, std::vector<DFace>> {
 public:
  DMesh() { attrn = 0; }
};

using DPair = vcg::tri::BasicVertexPair<DVertex>;
// vcglib allocates every candidate collapse with new and deletes it when it is popped or found
// out of date: millions per dense decimation, and malloc/free were ~10 % of its time (perf,
// 2026-12-04). While RunCollapse runs (the pool lives in its scope, on its thread), the candidates
// come from this free list of fixed-size blocks, released when the decimation ends. Addresses do
// not enter the heap's order (priority only), so the result does not change.
template <class T>
class BlockPool {
 public:
  BlockPool() { Current() = this; }
  ~BlockPool() { Current() = nullptr; }
  BlockPool(const BlockPool&) = delete;
  BlockPool& operator=(const BlockPool&) = delete;
  static void* Allocate(size_t n) {
    BlockPool* p = Current();
    return p && n == sizeof(T) ? p->Get() : ::operator new(n);
  }
  static void Release(void* q, size_t n) {
    BlockPool* p = Current();
    if (p && n == sizeof(T))
      p->Put(q);
    else
      ::operator delete(q);
  }

 private:
  union Block {
    Block* next;
    alignas(T) unsigned char bytes[sizeof(T)];
  };
  static constexpr size_t kChunk = size_t(1) << 14;
  static BlockPool*& Current() {
    thread_local BlockPool* current = nullptr;
    return current;
  }
  void* Get() {
    if (free_) {
      Block* b = free_;
      free_ = b->next;
      return b;
    }
    if (chunks_.empty() || used_ == kChunk) {
      chunks_.emplace_back(new Block[kChunk]);
      used_ = 0;
    }
    return &chunks_.back()[used_++];
  }
  void Put(void* q) {
    Block* b = static_cast<Block*>(q);
    b->next = free_;
    free_ = b;
  }
  std::vector<std::unique_ptr<Block[]>> chunks_;
  size_t used_ = 0;
  Block* free_ = nullptr;
};

// One collapse type per concurrent decimation: vcglib keeps its heap's validity counter
// (TriEdgeCollapse::GlobalMark) in a static of the collapse type, so the two halves of a split
// decimation (DecimateSplit) each need their own type, K = 0 and 1.
//
// The priority of a candidate collapse is vcglib's TriEdgeCollapseQuadric::ComputePriority,
// evaluated the same way in one pass (SinglePassPriority): vcglib's version collects the old
// normals of the faces around the edge into a std::vector allocated per candidate, moves both
// vertices to the new position, walks the faces again and moves the vertices back — a 1.2 M
// triangle decimation evaluates ~10 M candidates, and that allocation and second walk were a
// quarter of its time (perf, 2026-12-04). Here each face's new corners are read beside its
// unit normal, which each face keeps in its N() (set by RunCollapse's PerFaceNormalized — the
// same expression as vcg::NormalizedTriangleNormal — and refreshed around the kept vertex after
// each collapse, the only time corners move; nothing else of the collapse reads N()); every value is computed by the same expressions in the same order, so the priorities, and
// the decimated mesh, are bit-identical (tests/core/decimate_test.cpp compares
// against vcglib's own collapse: VcgPriority = true, WorkingResolutionParams::vcgPriority).
template <int K, bool VcgPriority>
class DCollapseT : public vcg::tri::TriEdgeCollapseQuadric<DMesh, DPair, DCollapseT<K, VcgPriority>,
                                                            vcg::tri::QInfoStandard<DVertex>> {
 public:
  using Base =
      vcg::tri::TriEdgeCollapseQuadric<DMesh, DPair, DCollapseT<K, VcgPriority>, vcg::tri::QInfoStandard<DVertex>>;
  using Coord = vcg::Point3d;
  // Base's default constructor: its other one would evaluate vcglib's priority first.
  DCollapseT(const DPair& p, int i, vcg::BaseParameterClass* pp) {
    this->localMark = i;
    this->pos = p;
    this->_priority = SinglePassPriority(pp);
  }
  double ComputePriority(vcg::BaseParameterClass* pp) override { return SinglePassPriority(pp); }
  static void* operator new(size_t n) { return BlockPool<DCollapseT>::Allocate(n); }
  static void operator delete(void* q, size_t n) { BlockPool<DCollapseT>::Release(q, n); }
  void Execute(DMesh& m, vcg::BaseParameterClass* pp) override {
    Base::Execute(m, pp);
    if (!VcgPriority) RefreshNormals(this->pos.V(1));
  }

 private:
  // The options QuadricCollapse sets (both checks, nothing else); any other set is vcglib's.
  static bool Supported(const vcg::tri::TriEdgeCollapseQuadricParameter& q) {
    return q.NormalCheck && q.QualityCheck && !q.AreaCheck && !q.HardQualityCheck && !q.HardNormalCheck &&
           !q.UseVertexWeight;
  }
  static void RefreshNormals(DVertex* v) {
    for (vcg::face::VFIterator<DFace> x(v); !x.End(); ++x) x.F()->N() = vcg::NormalizedTriangleNormal(*x.F());
  }

  // Over the faces of `from` that do not contain `other`: the smallest cosine between a face's
  // normal before and after `from` moves to `to`, and the smallest quality after.
  static void ScanFan(DVertex* from, DVertex* other, const Coord& to, double& minCos, double& minQual) {
    for (vcg::face::VFIterator<DFace> x(from); !x.End(); ++x) {
      if (x.V1() == other || x.V2() == other) continue;
      const DFace& f = *x.F();
      const Coord p0 = f.cP(0), p1 = f.cP(1), p2 = f.cP(2);
      const Coord q0 = f.cV(0) == from ? to : p0, q1 = f.cV(1) == from ? to : p1, q2 = f.cV(2) == from ? to : p2;
      const Coord& before = f.cN();  // vcg::NormalizedTriangleNormal(f), kept up to date
      const Coord after = vcg::Normal(q0, q1, q2).Normalize();
      minCos = std::min(minCos, after.dot(before));
      minQual = std::min(minQual, vcg::Quality(q0, q1, q2));
    }
  }

  double SinglePassPriority(vcg::BaseParameterClass* base) {
    auto* pp = static_cast<vcg::tri::TriEdgeCollapseQuadricParameter*>(base);
    if (VcgPriority || !Supported(*pp)) return Base::ComputePriority(base);
    DVertex* v0 = this->pos.V(0);
    DVertex* v1 = this->pos.V(1);
    this->ComputePosition(base);
    const Coord to = this->optimalPos;
    double minCos = std::numeric_limits<double>::max(), newQual = std::numeric_limits<double>::max();
    ScanFan(v0, v1, to, minCos, newQual);
    ScanFan(v1, v0, to, minCos, newQual);
    vcg::math::Quadric<double> qq = v0->Qd();
    qq += v1->Qd();
    double quadErr = pp->ScaleFactor * qq.Apply(to);
    if (newQual > pp->QualityThr) newQual = pp->QualityThr;
    if (minCos > pp->CosineThr) minCos = pp->CosineThr;
    minCos = std::fabs((minCos + 1.0) / 2.0);
    quadErr = std::max(quadErr, pp->QuadricEpsilon);
    if (quadErr <= pp->QuadricEpsilon) quadErr *= vcg::Distance(v0->cP(), v1->cP());
    this->_priority = quadErr / (newQual * minCos);
    return this->_priority;
  }
};

// vcglib hands out per-vertex user bits from a static counter of the vertex type
// (VertexType::NewBitFlag / DeleteBitFlag, which UpdateFlags::FaceBorderFromVF uses, also inside
// the quadric collapse's Init and the isotropic remeshing): DMesh code that can run on two
// threads at once (the two halves of DecimateSplit, concurrent callers of WorkingResolution)
// holds this lock around those calls. The sanitizer build's vcglib assertion found the race.
std::mutex& BitFlagLock() {
  static std::mutex lock;
  return lock;
}

// FNV-1a over the mesh's arrays and the parameters: identifies a repeated request.
std::uint64_t Fingerprint(const TriData& m, const WorkingResolutionParams& p) {
  std::uint64_t h = 1469598103934665603ull;
  auto eat = [&](const void* data, size_t n) {
    const unsigned char* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  eat(m.V.data(), m.V.size() * sizeof(Vec3));
  eat(m.F.data(), m.F.size() * sizeof(Tri));
  eat(&p.maxFaces, sizeof p.maxFaces);
  eat(&p.preserveBoundary, sizeof p.preserveBoundary);
  eat(&p.splitMinFaces, sizeof p.splitMinFaces);
  eat(&p.vcgPriority, sizeof p.vcgPriority);
  return h;
}

// The three latest decimations of this process: in a MeshLab pipeline "Compute Fitmaps" and
// "Fitmap Quad Simplification" both need M' of the same layer (M'_F, M'_S and the count pass's
// start, quad_simplify.h), and on 5 M triangles one decimation takes a minute. Kept: three
// small meshes.
struct Decimation {
  std::uint64_t key = 0;
  size_t nv = 0, nf = 0;
  DecimateResult result;
};
struct RecentDecimations {
  std::mutex lock;
  Decimation slot[3];  ///< [0] the most recent
};
RecentDecimations& Memo() {
  static RecentDecimations memo;
  return memo;
}

DecimateResult Decimate(const TriData& m, const WorkingResolutionParams& p, vcg::CallBackPos* cb);

// vcglib's quadric collapse does not commute with the unit: its priority is the quadric error
// times ScaleFactor = 1e8 / diag^6 (ScaleIndependent), clamped below at an absolute QuadricEpsilon
// (1e-15), so the order in flat regions depends on the size (fandisk.off x 2^-14, exact in float:
// another 8 000-triangle decimation, and 495 patches for 430; x 2^10: 432). Decimate runs on a
// copy scaled by a power of two to a bounding-box diagonal in [kUnitDiagonal, 2 kUnitDiagonal) and
// the result is scaled back, both exact: a power-of-two scaling of an input gives its decimation
// scaled. kUnitDiagonal = 1.25 puts the meshes whose figures the docs and tests quote (bunny00
// 1.60, fandisk 1.45, elephant 1.37, rotor 1.41, camel and turbine 1.43, the tests' cigar 2.01)
// inside the range: they decimate as before. Any range gives scale invariance; this one keeps them.
constexpr double kUnitDiagonal = 1.25;
DecimateResult DecimateAtUnitScale(const TriData& m, const WorkingResolutionParams& p, vcg::CallBackPos* cb) {
  const double diag = BBoxDiagonal(m.V);
  int e = 0;
  std::frexp(diag / kUnitDiagonal, &e);  // diag / 1.25 = f 2^e, f in [0.5, 1): diag 2^(1 - e) in [1.25, 2.5)
  if (!(diag > 0) || !std::isfinite(diag) || e == 1) return Decimate(m, p, cb);
  TriData unit = m;
  for (Vec3& v : unit.V) v *= std::ldexp(1.0, 1 - e);
  DecimateResult r = Decimate(unit, p, cb);
  for (Vec3& v : r.mesh.V) v *= std::ldexp(1.0, e - 1);
  return r;
}

void ToDMesh(const TriData& m, DMesh& d) {
  auto vi = vcg::tri::Allocator<DMesh>::AddVertices(d, m.V.size());
  for (size_t i = 0; i < m.V.size(); ++i, ++vi) vi->P() = vcg::Point3d(m.V[i][0], m.V[i][1], m.V[i][2]);
  auto fi = vcg::tri::Allocator<DMesh>::AddFaces(d, m.F.size());
  for (size_t f = 0; f < m.F.size(); ++f, ++fi)
    for (int k = 0; k < 3; ++k) fi->V(k) = &d.vert[m.F[f][k]];
}
TriData FromDMesh(DMesh& d) {
  vcg::tri::Allocator<DMesh>::CompactEveryVector(d);
  TriData t;
  t.V.reserve(d.vert.size());
  for (const auto& v : d.vert) t.V.push_back(Vec3(v.cP()[0], v.cP()[1], v.cP()[2]));
  t.F.reserve(d.face.size());
  for (const auto& f : d.face)
    t.F.push_back({int(vcg::tri::Index(d, f.cV(0))), int(vcg::tri::Index(d, f.cV(1))), int(vcg::tri::Index(d, f.cV(2)))});
  return t;
}

// vcglib's edge-midpoint refinement (every edge) until the mesh has `minFaces` triangles.
DecimateResult Refine(const TriData& m, int minFaces) {
  DecimateResult r;
  DMesh d;
  ToDMesh(m, d);
  while (d.fn < minFaces) {
    vcg::tri::UpdateTopology<DMesh>::FaceFace(d);
    vcg::tri::Refine<DMesh>(d, vcg::tri::MidPoint<DMesh>(&d), 0);
    ++r.refinements;
  }
  r.mesh = FromDMesh(d);
  return r;
}
int MaxValence(const TriData& m) {
  std::vector<int> val(m.V.size(), 0);
  for (const auto& f : m.F)
    for (int v : f) ++val[v];
  int mx = 0;
  for (int x : val) mx = std::max(mx, x);
  return mx;
}

// vcglib's isotropic remeshing to about `faces` triangles (edge length from the area), five
// iterations, projected onto the input; boundaries and creases above 30 degrees kept.
DecimateResult Remesh(const TriData& m, int faces) {
  DecimateResult r;
  DMesh d, ref;
  ToDMesh(m, d);
  ToDMesh(m, ref);
  double area = 0;
  for (const auto& f : m.F) area += 0.5 * (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]).norm();
  vcg::tri::IsotropicRemeshing<DMesh>::Params ip;
  ip.SetTargetLen(std::sqrt(4.0 * area / (std::sqrt(3.0) * std::max(1, faces))));
  ip.SetFeatureAngleDeg(30);
  ip.iter = 5;
  // No Hausdorff test on the moves (projection onto the input keeps the shape). maxSurfDist has no
  // default in vcglib's Params, and ProjectToSurface reads it even with surfDistCheck off (its
  // search radius is 1.5 maxSurfDist): left unset, the remesh depended on stack garbage (1 250 to
  // 1 256 triangles on oblong-shuffled.off from run to run, found by CI and valgrind). 1 % of the
  // bbox diagonal, MeshLab's own default for this filter. Not the whole diagonal: projecting from
  // anywhere left a cone's apex (cone2000.off) at valence 277 with edges 5x the target, and its
  // simplification ran past 300 s (docs/robustness.md "Same input, same result").
  ip.surfDistCheck = false;
  ip.maxSurfDist = 0.01 * BBoxDiagonal(m.V);
  vcg::tri::UpdateTopology<DMesh>::FaceFace(d);
  vcg::tri::UpdateTopology<DMesh>::VertexFace(d);
  vcg::tri::UpdateNormal<DMesh>::PerFaceNormalized(d);
  std::lock_guard<std::mutex> g(BitFlagLock());
  vcg::tri::IsotropicRemeshing<DMesh>::Do(d, ref, ip);
  vcg::tri::UpdateTopology<DMesh>::FaceFace(d);
  if (vcg::tri::Clean<DMesh>::CountNonManifoldEdgeFF(d) > 0 || vcg::tri::Clean<DMesh>::CountNonManifoldVertexFF(d, false) > 0)
    return r;  // empty: not manifold
  r.mesh = FromDMesh(d);
  return r;
}

// Faces whose corners are collinear or coincident (zero cross product) or not finite.
int ZeroAreaFaces(const TriData& m) {
  int n = 0;
  for (const auto& f : m.F) {
    const Vec3 c = (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]);
    n += !(c.norm() > 0) || !c.allFinite();
  }
  return n;
}

// `m` with its zero-area faces flipped away: a face whose corner lies on the opposite edge is
// flipped with its neighbour across that edge (vcglib's RemoveTVertexByFlip, MeshLab's "Remove
// T-Vertices by Edge Flip"; a flip is taken only where it raises the worse of the two triangles'
// quality, so the loop ends, and the link condition keeps the mesh manifold and oriented). The
// threshold 1e6 (height below a millionth of the longest side) leaves every other face alone.
// False when a zero-area face is left: coincident corners, or no flip that helps (a boundary edge).
bool FlipZeroAreaFaces(const TriData& m, TriData& out, int& flips) {
  // Coincident corners (a repeated index, or two at one place) no flip removes; a repeated index
  // would also trip vcglib's face-face topology (an assertion; the fuzzer's raw regression).
  for (const auto& f : m.F) {
    const double shortest = std::min({(m.V[f[1]] - m.V[f[0]]).norm(), (m.V[f[2]] - m.V[f[1]]).norm(),
                                      (m.V[f[0]] - m.V[f[2]]).norm()});
    if (!(shortest > 0)) return false;
  }
  // vcglib's flip asserts an edge-manifold, consistently oriented mesh (WorkingResolution's
  // precondition, which the fuzzer's raw target breaks on purpose): each directed edge once.
  std::unordered_set<std::uint64_t> directed;
  directed.reserve(3 * m.F.size());
  for (const auto& f : m.F)
    for (int k = 0; k < 3; ++k)
      if (!directed.insert(std::uint64_t(std::uint32_t(f[k])) << 32 | std::uint32_t(f[(k + 1) % 3])).second)
        return false;
  DMesh d;
  ToDMesh(m, d);
  vcg::tri::UpdateTopology<DMesh>::FaceFace(d);
  flips = vcg::tri::Clean<DMesh>::RemoveTVertexByFlip(d, 1e6f, true);
  out = FromDMesh(d);
  return ZeroAreaFaces(out) == 0;
}

}  // namespace

DecimateResult WorkingResolution(const TriData& m, const WorkingResolutionParams& p, vcg::CallBackPos* cb) {
  DecimateResult r;
  const int valence = p.maxValence > 0 ? MaxValence(m) : 0;
  if (valence > p.maxValence && p.maxValence > 0) {
    const auto t0 = std::chrono::steady_clock::now();
    const int faces = std::max(p.minFaces, p.maxFaces > 0 ? std::min(int(m.F.size()), p.maxFaces) : int(m.F.size()));
    r = Remesh(m, faces);
    if (r.mesh.F.empty()) r.remeshRefusedValence = valence;  // not manifold: no start mesh
    else r.remeshedValence = valence;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
  if (p.minFaces > 0 && !m.F.empty() && int(m.F.size()) < p.minFaces) return Refine(m, p.minFaces);
  if (p.maxFaces <= 0 || int(m.F.size()) <= p.maxFaces) {
    r.mesh = m;
    return r;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::uint64_t key = Fingerprint(m, p);
  RecentDecimations& memo = Memo();
  {
    std::lock_guard<std::mutex> g(memo.lock);
    for (const Decimation& d : memo.slot)
      if (d.key == key && d.nv == m.V.size() && d.nf == m.F.size()) {
        r = d.result;
        r.reused = true;
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return r;
      }
  }
  // vcglib's quadrics are NaN on zero-area faces (its collapse asserts on them; the fuzzer found
  // it). Before 2026-12-04 such a mesh was used at full resolution: one collinear sliver among a
  // dense scan's millions of triangles made every later stage run on all of them (triceratops.off
  // refined to 362k triangles has 22 after MeshLab's float rounding: its budget run took 108 s).
  // Now they are flipped away on the copy; only a face with coincident corners stops it.
  TriData repaired;
  int flips = 0;
  const bool degenerate = ZeroAreaFaces(m) > 0;
  if (degenerate && !FlipZeroAreaFaces(m, repaired, flips)) {
    r.mesh = m;
    r.skippedDegenerate = true;
    return r;
  }
  r = DecimateAtUnitScale(degenerate ? repaired : m, p, cb);
  r.zeroAreaFlips = flips;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::lock_guard<std::mutex> g(memo.lock);
  memo.slot[2] = std::move(memo.slot[1]);
  memo.slot[1] = std::move(memo.slot[0]);
  memo.slot[0] = Decimation{key, m.V.size(), m.F.size(), r};
  return r;
}

namespace {
// vcglib's quadric edge collapse of `d` down to `target` faces. Progress (when cb) runs from
// `from` to `to` percent.
template <class Collapse>
void RunCollapse(DMesh& d, int target, bool preserveBoundary, vcg::CallBackPos* cb, int from, int to) {
  vcg::tri::TriEdgeCollapseQuadricParameter qp;
  qp.PreserveTopology = true;
  qp.FastPreserveBoundary = preserveBoundary;  // what MeshLab's filter uses for "Preserve Boundary"
  qp.OptimalPlacement = true;
  qp.QualityCheck = true;
  qp.NormalCheck = true;
  qp.NormalThrRad = M_PI / 4.0;
  BlockPool<Collapse> pool;  // before the session: it deletes its remaining candidates into the pool
  vcg::LocalOptimization<DMesh> session(d, &qp);
  {
    std::lock_guard<std::mutex> g(BitFlagLock());
    vcg::tri::UpdateTopology<DMesh>::VertexFace(d);
    vcg::tri::UpdateFlags<DMesh>::FaceBorderFromVF(d);
    vcg::tri::UpdateNormal<DMesh>::PerFaceNormalized(d);  // also the one-pass priority's N() (DCollapseT)
    session.Init<Collapse>();
  }
  session.SetTargetSimplices(target);
  session.SetTimeBudget(0.1f);  // returns ten times a second for progress
  const int toDelete = d.fn - target;
  while (session.DoOptimization() && d.fn > target)
    if (cb)
      cb(from + (to - from) * (100 - 100 * (d.fn - target) / std::max(1, toDelete)) / 100,
         "Working resolution: decimating");
  session.Finalize<Collapse>();
}
// With the one-pass priority, or with vcglib's own (`vcgPriority`, the tests' reference).
template <int K>
void QuadricCollapse(DMesh& d, int target, bool preserveBoundary, bool vcgPriority, vcg::CallBackPos* cb, int from = 0,
                     int to = 100) {
  if (vcgPriority)
    RunCollapse<DCollapseT<K, true>>(d, target, preserveBoundary, cb, from, to);
  else
    RunCollapse<DCollapseT<K, false>>(d, target, preserveBoundary, cb, from, to);
}

// Halves of `m` at the median face centroid along the longest bbox axis. A vertex used by both
// halves is a cut vertex: its quality in each half is its index in `m` (else -1).
void SplitInTwo(const TriData& m, DMesh half[2]) {
  Vec3 lo = m.V.empty() ? Vec3::Zero() : m.V[0], hi = lo;
  for (const Vec3& v : m.V) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  std::vector<double> c(m.F.size());
  for (size_t f = 0; f < m.F.size(); ++f) c[f] = m.V[m.F[f][0]][axis] + m.V[m.F[f][1]][axis] + m.V[m.F[f][2]][axis];
  std::vector<double> sorted = c;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<unsigned char> side(m.F.size()), use(m.V.size(), 0);
  for (size_t f = 0; f < m.F.size(); ++f) {
    side[f] = c[f] < median ? 0 : 1;
    for (int v : m.F[f]) use[v] |= 1 << side[f];
  }
  for (int h = 0; h < 2; ++h) {
    std::vector<int> local(m.V.size(), -1);
    int nv = 0, nf = 0;
    for (size_t v = 0; v < m.V.size(); ++v)
      if (use[v] & (1 << h)) local[v] = nv++;
    for (unsigned char s : side) nf += s == h;
    vcg::tri::Allocator<DMesh>::AddVertices(half[h], nv);
    for (size_t v = 0; v < m.V.size(); ++v)
      if (local[v] >= 0) {
        DVertex& dv = half[h].vert[local[v]];
        dv.P() = vcg::Point3d(m.V[v][0], m.V[v][1], m.V[v][2]);
        dv.Q() = use[v] == 3 ? double(v) : -1.0;
      }
    auto fi = vcg::tri::Allocator<DMesh>::AddFaces(half[h], nf);
    for (size_t f = 0; f < m.F.size(); ++f)
      if (side[f] == h) {
        for (int k = 0; k < 3; ++k) fi->V(k) = &half[h].vert[local[m.F[f][k]]];
        ++fi;
      }
  }
}

// The two decimated halves welded at their cut vertices (which no collapse moved: they are
// boundary vertices of their half, and FastPreserveBoundary keeps those).
void WeldHalves(DMesh half[2], DMesh& out) {
  TriData merged;
  std::unordered_map<long long, int> cut;
  for (int h = 0; h < 2; ++h) {
    vcg::tri::Allocator<DMesh>::CompactEveryVector(half[h]);
    std::vector<int> index(half[h].vert.size());
    for (size_t v = 0; v < half[h].vert.size(); ++v) {
      const DVertex& dv = half[h].vert[v];
      const long long g = dv.cQ() >= 0 ? (long long)(dv.cQ()) : -1;
      if (g >= 0) {
        auto it = cut.find(g);
        if (it != cut.end()) { index[v] = it->second; continue; }
        cut.emplace(g, int(merged.V.size()));
      }
      index[v] = int(merged.V.size());
      merged.V.push_back(Vec3(dv.cP()[0], dv.cP()[1], dv.cP()[2]));
    }
    for (const auto& f : half[h].face)
      merged.F.push_back({index[vcg::tri::Index(half[h], f.cV(0))], index[vcg::tri::Index(half[h], f.cV(1))],
                          index[vcg::tri::Index(half[h], f.cV(2))]});
  }
  ToDMesh(merged, out);
}

// Large inputs on two threads (paper §4's M' of a 5 M-triangle scan is a minute of collapses on
// one): each half decimated to its share of 120 % of the target with the cut kept (a boundary of
// the half), the halves welded, then one pass over the whole to the target, which also
// coarsens the strip along the cut. Every collapse of a half is one the whole mesh allows (an
// edge of two non-cut vertices has its whole neighbourhood in the half: the same quadrics and
// link condition), so the result keeps the topology like the one-thread decimation. Under load
// (the other core busy) it costs what one thread does. Measured in docs/multires.md.
void DecimateSplit(const TriData& m, const WorkingResolutionParams& p, vcg::CallBackPos* cb, DMesh& d) {
  DMesh half[2];
  SplitInTwo(m, half);
  const double share = 1.2 * p.maxFaces / double(m.F.size());
  const int target0 = std::max(1, int(share * half[0].fn)), target1 = std::max(1, int(share * half[1].fn));
  std::thread other([&] { QuadricCollapse<1>(half[1], target1, true, p.vcgPriority, nullptr); });
  QuadricCollapse<0>(half[0], target0, true, p.vcgPriority, cb, 0, 90);  // progress from this thread only
  other.join();
  WeldHalves(half, d);
  QuadricCollapse<0>(d, p.maxFaces, p.preserveBoundary, p.vcgPriority, cb, 90, 100);
}

DecimateResult Decimate(const TriData& m, const WorkingResolutionParams& p, vcg::CallBackPos* cb) {
  const auto t0 = std::chrono::steady_clock::now();
  DecimateResult r;
  DMesh d;
  if (p.splitMinFaces > 0 && m.F.size() >= size_t(p.splitMinFaces) && size_t(p.maxFaces) * 2 <= m.F.size() &&
      p.preserveBoundary) {
    DecimateSplit(m, p, cb, d);
    r.split = true;
  } else {
    ToDMesh(m, d);
    QuadricCollapse<0>(d, p.maxFaces, p.preserveBoundary, p.vcgPriority, cb);
  }
  r.mesh = FromDMesh(d);
  r.decimated = true;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}
}  // namespace

StartMesh ChooseStartMesh(const TriData& input, const StartMeshParams& p, vcg::CallBackPos* cb) {
  WorkingResolutionParams wf, wp;
  wf.maxFaces = p.workingFaces == 0 ? 0 : std::max(p.workingFaces, p.fitmapsWorkingFaces);
  wp.maxFaces = p.workingFaces;
  wp.minFaces = p.minFaces;
  wp.maxValence = p.maxValence;
  StartMesh s;
  const DecimateResult base = WorkingResolution(input, wf, cb);
  s.work = WorkingResolution(base.mesh, wp, cb);
  DecimateResult& work = s.work;
  work.seconds += base.seconds;
  work.decimated = work.decimated || base.decimated;
  if (work.remeshRefusedValence > 0) {
    s.error = "the input has a vertex of valence " + std::to_string(work.remeshRefusedValence) +
              ", so the control mesh would start from an isotropic remesh of it (docs/robustness.md), and that remesh is "
              "not manifold (vcglib's remeshing across narrow gaps: cracks or an unwelded seam?); weld the input first "
              "(Filters > Cleaning and Repairing > Merge Close Vertices) or remesh it yourself (Remeshing, Simplification "
              "and Reconstruction > Remeshing: Isotropic Explicit Remeshing)";
    return s;
  }
  if (base.skippedDegenerate || work.skippedDegenerate)
    s.warnings.push_back("the input has zero-area triangles that edge flips cannot remove (coincident corners), which the "
                         "decimation cannot handle: simplifying from the full input (slower; Filters > Cleaning and Repairing > "
                         "Remove Zero Area Faces avoids it)");
  if (const int flips = std::max(base.zeroAreaFlips, work.zeroAreaFlips); flips > 0)
    s.notes.push_back("the input has zero-area triangles: " + std::to_string(flips) +
                      " edge flips removed them from the copy that is decimated (the input is unchanged)");
  if (work.remeshedValence > 0)
    s.notes.push_back("the input has a vertex of valence " + std::to_string(work.remeshedValence) +
                      ": the control mesh starts from an isotropic remesh of it (" + std::to_string(work.mesh.F.size()) +
                      " triangles, " + std::to_string(work.seconds) + " s); projections and errors refer to the input");
  if (work.refinements > 0)
    s.notes.push_back("the input has only " + std::to_string(input.F.size()) +
                      " triangles: the control mesh starts from it refined " + std::to_string(work.refinements) +
                      " times at edge midpoints (" + std::to_string(work.mesh.F.size()) + " triangles, the same surface)");
  if (work.decimated)
    s.notes.push_back("working resolution " + std::to_string(work.mesh.F.size()) + " triangles (the input has " +
                      std::to_string(input.F.size()) + "), decimated in " + std::to_string(work.seconds) +
                      " s; projections and errors refer to the full input");
  s.differs = work.decimated || work.refinements > 0 || work.remeshedValence > 0;
  return s;
}

}  // namespace vcgext
