/// \file simplifier.h
/// The Simplifier: one simplification pass (Fitmaps §3.2–3.4) on a quad mesh K — its state, the
/// per-element projections and checks every step runs (inline here: the hot path), and its
/// operations, defined in simplifier.cpp (the caches, the pass in cost order, the final checks and
/// SimplifyOnce around it), simplifier_step.cpp (one step: collapse, doublets, swaps, local fit and
/// its checks) and swap_sweep.cpp (the swap sweep after the pass). Internal to vcg_ext/quad.
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "vcg_ext/quad/cc_limit.h"
#include "vcg_ext/quad/quad_mesh.h"
#include "vcg_ext/quad/simplify_internal.h"

namespace vcgext {
namespace simplify_internal {

using quad::OpResult;
using quad::QuadMesh;


struct FaceInfo {
  Vec3 c = Vec3::Zero();
  double S = 0, M = 0;
  bool ok = false;  ///< centre projects onto the input with an agreeing normal
  int hit = -1;     ///< input triangle hit by the projection (-1: none)
  double dist = 0;  ///< |phi(c) - c| (valid when hit >= 0)
};

class Simplifier {
 public:
  // `start`: the mesh the control mesh starts from (M' of §4, or `in` itself); its vertices are
  // the initial control vertices, so the pinned boundary corners are its own.
  Simplifier(const TriData& in, const TriData& start, const EmbreeScene& scene, const std::vector<double>& S,
             const std::vector<double>& M, const QuadSimplifyParams& p, QuadSimplifyResult& res);
  bool Pinned(int v) const { return v < int(pinned_.size()) && pinned_[v]; }

  quad::LayoutGate* gate = nullptr;  ///< set: the target comes from the count pass beside this one
  quad::LayoutGate* publishTo = nullptr;  ///< set: this is that count pass, on the layout pass's start
  bool cancelled = false;      ///< the gate cancelled this pass (Run returned early)
  double gateWait = 0;         ///< seconds this pass waited for the count

  QuadMesh K;

  // projection phi along the line (either side), nearest hit within maxDist (default maxDist_).
  // `side`: where the input probably is (see EmbreeScene::NearestOnLine: 1 ray instead of 2 when
  // the guess is right and nothing else lies within window_; the answer never depends on it).
  EmbreeScene::Hit LineHit(const Vec3& c, const Vec3& n, double maxDist = -1, signed char* side = nullptr) const {
    return scene_.NearestOnLine(c, n, maxDist < 0 ? maxDist_ : maxDist, window_, side);
  }

  // projects a face centre c (limit normal n) and fills fi's hit fields; false: no hit
  bool Project(const Vec3& c, const Vec3& n, FaceInfo& fi, signed char* side) const {
    EmbreeScene::Hit h = LineHit(c, n, -1, side);
    if (!h.valid) return false;
    fi.S = AtHit(S_, h);
    fi.M = AtHit(M_, h);
    fi.ok = FN_[h.face].dot(n) > 0;
    fi.hit = h.face;
    fi.dist = std::abs(h.t);
    return true;
  }

  // vp given: the corners' vertex points, during the checks of a step (`memo` valid)
  FaceInfo EvalFace(int f, const Vec3* vp = nullptr, const quad::QuadMemo* memo = nullptr) const {
    FaceInfo fi;
    Vec3 n;
    if (!(vp ? quad::FaceCentreLimit(*memo, f, vp, &fi.c, &n) : quad::FaceCentreLimit(K, f, &fi.c, &n))) return fi;
    if (!Project(fi.c, n, fi, FSide(f))) {
      // no hit: keep S/M from the closest point so costs stay meaningful, but flag it
      EmbreeScene::Hit h = scene_.ClosestPoint(fi.c);
      if (h.valid) {
        fi.S = AtHit(S_, h);
        fi.M = AtHit(M_, h);
      }
      fi.ok = false;
    }
    return fi;
  }

  // a per-input-vertex field (S or M) interpolated at a hit on the input
  double AtHit(const std::vector<double>& A, const EmbreeScene::Hit& h) const {
    const Tri& t = in_.F[h.face];
    return (1.0 - h.u - h.v) * A[t[0]] + h.u * A[t[1]] + h.v * A[t[2]];
  }
  // tolerance of the geometric guard at an input hit
  double DevTol(double m) const {
    double t = p_.deviationFactor * m;
    return p_.maxDeviationPercent > 0 ? std::min(t, p_.maxDeviationPercent / 100.0 * diag_) : t;
  }
  // geometric guard on one limit sample: projects along its normal onto the input, agreeing
  // normals, within DevTol; boundary samples (no normal): closest point within DevTol
  bool SampleOk(const Vec3& pos, const Vec3* n, signed char* side) const {
    if (!n) {
      EmbreeScene::Hit h = scene_.ClosestPoint(pos, maxDist_);
      return h.valid && (h.point - pos).norm() <= DevTol(AtHit(M_, h));
    }
    // no hit beyond the largest possible tolerance can pass
    EmbreeScene::Hit h = LineHit(pos, *n, std::min(maxDist_, DevTol(maxM_)), side);
    return h.valid && FN_[h.face].dot(*n) > 0 && std::abs(h.t) <= DevTol(AtHit(M_, h));
  }
  // geometric guard on face g (its corners' vertex points vp): centre (info) and edge midpoints
  // (each edge once: skipped when the neighbour also touches W and has the smaller index).
  // During the checks of a step (`memo` valid).
  bool FaceDeviationOk(int g, const Vec3 vp[4], const FaceInfo& fi, const quad::QuadMemo& memo) const {
    if (fi.hit < 0 || !fi.ok || fi.dist > DevTol(fi.M)) return false;
    signed char side = FSide(g) ? *FSide(g) : 1;  // guess: the edge midpoints lie on the centre's side
    for (int k = 0; k < 4; ++k) {
      int h = memo.AcrossEdge(g, k);
      if (h >= 0 && h < g && faceTouchesW(h)) continue;
      Vec3 pos, n;
      bool hasN = false;
      if (!quad::EdgeMidLimit(memo, g, k, vp, &pos, &n, &hasN)) return false;
      if (!SampleOk(pos, hasN ? &n : nullptr, &side)) return false;
    }
    return true;
  }
  bool faceTouchesW(int g) const {
    for (int x : K.F[g])
      if (vmarkOfW(x)) return true;
    return false;
  }

  // interior vertex: its limit normal agrees with the input normal where it projects
  bool VertexOk(int v, int* hitFace = nullptr) const {
    if (hitFace) *hitFace = -1;
    if (!K.VertAlive(v) || K.IsBoundary(v)) return true;
    Vec3 pos, n;
    if (!quad::VertexLimitFrame(K, v, &pos, &n)) return false;
    EmbreeScene::Hit h = LineHit(pos, n, -1, VSide(v));
    if (hitFace && h.valid) *hitFace = h.face;
    return h.valid && FN_[h.face].dot(n) > 0;
  }
  // A vertex of W right after LocalFit: its limit point was solved onto its target, a point of
  // input triangle `hit`; if it is there (within 10x the solve tolerance), the line along its
  // normal meets the input at that point first, so the ray cast of VertexOk is skipped.
  bool VertexOkAfterFit(int v, const Vec3& target, int hit, int* hitFace) const {
    if (hit < 0 || !K.VertAlive(v) || K.IsBoundary(v)) return VertexOk(v, hitFace);
    Vec3 pos, n;
    if (!quad::VertexLimitFrame(K, v, &pos, &n)) return false;
    if ((pos - target).norm() > 10 * tol_) return VertexOk(v, hitFace);
    *hitFace = hit;
    return FN_[hit].dot(n) > 0;
  }
  // Elements only in the 2-ring of the moved vertices move little: if their new limit normal
  // still agrees with the input triangle their last projection hit, no ray is cast (the full
  // test runs otherwise, and on the final mesh).
  bool VertexOkFast(int v, int* hitFace) const {
    if (!K.VertAlive(v) || K.IsBoundary(v)) { *hitFace = -1; return true; }
    if (vhit_[v] >= 0) {
      Vec3 pos, n;
      if (quad::VertexLimitFrame(K, v, &pos, &n) && FN_[vhit_[v]].dot(n) > 0) { *hitFace = vhit_[v]; return true; }
    }
    return VertexOk(v, hitFace);
  }

  Vec3 BoundaryTarget(const Vec3& p) const {
    const EmbreeScene::Hit h = scene_.ClosestBoundaryPoint(p);
    return h.valid ? h.point : p;
  }

  // hitFace: the input triangle the target lies on when it is a projection along the normal (else -1)
  Vec3 VertexTarget(int v, int* hitFace = nullptr) const {
    if (hitFace) *hitFace = -1;
    if (Pinned(v)) return start_.V[v];
    if (K.IsBoundary(v)) return BoundaryTarget(quad::VertexLimit(K, v));
    Vec3 pos, n;
    if (!quad::VertexLimitFrame(K, v, &pos, &n)) return quad::VertexLimit(K, v);
    EmbreeScene::Hit hl = LineHit(pos, n, -1, VSide(v));
    if (hl.valid) {
      if (hitFace) *hitFace = hl.face;
      return hl.point;
    }
    EmbreeScene::Hit h = scene_.ClosestPoint(pos, maxDist_);
    return h.valid ? h.point : pos;
  }

  // Final pass: every control point re-interpolates the projection of its limit point (one
  // global solve), so all limit vertices lie on the input again (the local fits perturb the
  // 2-ring of each step, §3.4).
  quad::InterpolationStats Reinterpolate();

  // Limit positions cached between steps (used by Cost and MTest only, which run on committed
  // states); invalidated for the 1-ring of W after each committed step.
  const Vec3& Lim(int v) const {
    if (!limOk_[v]) { lim_[v] = quad::VertexLimit(K, v); limOk_[v] = 1; }
    return lim_[v];
  }

  // side guesses for LineHit per vertex / face slot (the side of its last projection)
  signed char* VSide(int v) const { return v < int(vside_.size()) ? &vside_[v] : nullptr; }
  signed char* FSide(int f) const { return f < int(fside_.size()) ? &fside_[f] : nullptr; }
  bool vmarkOfW(int v) const { return wmarkOf_[v] == wmark_; }

  // Catmull-Clark vertex point of a corner of a checked face, during Step. It depends on the
  // positions and faces of the vertex's 1-ring, which only change for vertices of R1_ =
  // ring1(W): W holds every moved vertex and every vertex of a face the step's operators edited.
  // So for the others the value of an earlier step is still exact (persistent cache,
  // invalidated for R1_ at each commit); R1_'s are computed once per step (epoch cache).
  // Sequential: claims the slot of corner x if its vertex point must be computed in this step
  // (returns true once per step and vertex; the caller computes it with ComputeVertexPoint).
  bool ClaimVertexPoint(int x) {
    if (vmarkOf_[x] == vmark_) {  // in R1_ (the last CollectRing)
      if (vpStamp_[x] == vpEpoch_) return false;
      vpStamp_[x] = vpEpoch_;
      return true;
    }
    if (!vpcOk_[x]) { vpcOk_[x] = 1; return true; }
    return false;
  }
  // Any thread, once per claimed x (distinct slots, no race).
  void ComputeVertexPoint(int x, const quad::QuadMemo& memo) {
    if (vmarkOf_[x] == vmark_) vp_[x] = quad::VertexPoint(memo, x);
    else vpc_[x] = quad::VertexPoint(K, x);
  }
  const Vec3& RegionVertexPoint(int x) const { return vmarkOf_[x] == vmark_ ? vp_[x] : vpc_[x]; }

  double Cost(int f, int k, const FaceInfo& fi) const {
    int a = K.F[f][k], c = K.F[f][k + 2];
    if (K.IsBoundary(a) && K.IsBoundary(c)) return -1;
    double d = (Lim(a) - Lim(c)).norm();
    double cost = d * (fi.S + 1e-9 / std::max(diag_, 1e-300));
    if (p_.valenceWeight > 0) cost *= std::pow(1.0 + p_.valenceWeight, ValenceDefectChange(f, k));
    return cost;
  }
  // Change of the summed valence defect of face f's corners when its diagonal k collapses: the
  // merged corner gets both corners' faces less the two copies of f, the other two lose f.
  int ValenceDefectChange(int f, int k) const {
    const int a = K.F[f][k], b = K.F[f][k + 1], c = K.F[f][k + 2], d = K.F[f][(k + 3) & 3];
    auto defect = [&](int v, int faces) { return std::abs(faces - (K.IsBoundary(v) ? 2 : 4)); };
    auto val = [&](int v) { return int(K.VF(v).size()); };
    const int merged = K.IsBoundary(a) ? a : c;
    const int before = defect(a, val(a)) + defect(b, val(b)) + defect(c, val(c)) + defect(d, val(d));
    const int after = defect(merged, val(a) + val(c) - 2) + defect(b, val(b) - 1) + defect(d, val(d) - 1);
    return after - before;
  }

  // One heap entry per face: its cheaper diagonal (the other one is queued only if the cheaper
  // one fails the M test), which halves the heap traffic.
  void Push(int f) {
    ++stamp_[f];
    double c0 = Cost(f, 0, info_[f]), c1 = Cost(f, 1, info_[f]);
    int k = (c1 >= 0 && (c0 < 0 || c1 < c0)) ? 1 : 0;
    double c = k ? c1 : c0;
    double other = k ? c0 : c1;
    if (c >= 0) heap_.push(MakeEntry(c, f, k, stamp_[f], other));
  }

  // M-fitmap test (§3.3): every patch the collapse enlarges keeps diameter <= F_M at its centre.
  bool MTest(int f, int k) const {
    int a = K.F[f][k], c = K.F[f][k + 2];
    Vec3 la = Lim(a), lc = Lim(c);
    Vec3 merged = K.IsBoundary(a) ? la : K.IsBoundary(c) ? lc : Vec3(0.5 * (la + lc));
    for (int v : {a, c})
      for (int g : K.VF(v)) {
        if (g == f) continue;
        Vec3 q[4];
        for (int j = 0; j < 4; ++j) {
          int x = K.F[g][j];
          q[j] = (x == a || x == c) ? merged : Lim(x);
        }
        Vec3 ctr = 0.25 * (q[0] + q[1] + q[2] + q[3]);
        double diam = 0;
        for (auto& x : q) diam = std::max(diam, (x - ctr).norm());
        if (diam > info_[g].M) return false;
      }
    return true;
  }

  void CollectRing(const std::vector<int>& seeds, std::vector<int>& out) {
    ++vmark_;
    out.clear();
    auto add = [&](int v) {
      if (v < 0 || !K.VertAlive(v) || vmarkOf_[v] == vmark_) return;
      vmarkOf_[v] = vmark_;
      out.push_back(v);
    };
    for (int s : seeds) add(s);
    size_t n0 = out.size();
    for (size_t i = 0; i < n0; ++i)
      for (int g : K.VF(out[i]))
        for (int j = 0; j < 4; ++j) add(K.F[g][j]);
  }

  // ---- one step (simplifier_step.cpp)
  // One simplification step: collapse + doublets + swaps + local fit, or nothing.
  // Returns 0 = done, 1 = topology refusal, 2 = flip refusal, 3 = geometric guard refusal.
  int Step(int f, int k);

  // After LocalFit: lfTargets_[i] / lfHit_[i] = the last round's target of W[i] and the input
  // triangle it lies on (-1: not a projection along the normal).
  void LocalFit(const std::vector<int>& W, int rounds = -1);

  // Test mode: every memoized entry the step's checks used must still be exact.
  void CountStaleMemos();
  // Undoes the step being checked (test mode: after verifying the memos the checks used).
  int Refuse(int code);

  // What a step's operators did (counted in the result when the step is committed).
  struct StepCounts {
    int doublets = 0, swaps = 0, corners = 0;
  };

  // Immediate doublet removal after a collapse (cascading from the vertices in dq); boundary
  // corners on flat stretches of the boundary are removed likewise (RemoveBoundaryCorner), which
  // is what coarsens open boundaries. False: an operator failed (the step must be rolled back).
  bool RemoveDoubletsAndCorners(std::vector<int> dq, std::vector<int>& affected, StepCounts& n);

  // Edge swaps in the 1-ring of the collapsed element's survivor s, while some strictly lowers
  // the valence energy (at most 4 passes).
  void SwapAround(int s, std::vector<int>& affected, StepCounts& n);

  // The elements whose limit a step changed, for its flip test: R1_ = the vertices of ring1(W)
  // (their limit normal depends on their 1-ring) and region_ = the faces incident to them (centre
  // limit depends on the corners' 1-rings); vpTodo_ = the corners whose vertex points must be
  // computed in this step (shared caches). Sequential.
  void CollectCheckRegion(const std::vector<int>& W);

  // The checks of a step on CollectCheckRegion's elements, into newVok_ / newVhit_ / newInfo_ /
  // devOk_. They only read shared state (each element writes its own result slots and its own
  // side hint — a hint picks which ray answers a later query, so at most the rounding of that
  // answer, and one element writes it —; each thread has its own memo), so they run in parallel
  // (checkThreads_). Every check runs; Verdict picks the first failure in the sequential order,
  // exactly as the sequential loop would.
  void RunChecks();

  // The checks' verdict: 0 = pass; 2 = an element that agreed with the input does not now (flip);
  // 3 = the geometric guard (the first failure in the sequential order gives the code).
  int Verdict() const;

  // The committed mesh and the caches of the checked elements; their costs re-queued.
  void CommitCaches();

  // Checks the pending operation on the moved ring W (local fit, then the step's checks):
  // 0 = kept (committed caches), else the refusal code (rolled back).
  int FitCheckCommit(const std::vector<int>& W);

  // ---- the swap sweep (swap_sweep.cpp)
  // Beyond the paper (issue 13, docs/quad.md "Swap sweep"): after the last collapse, every edge of
  // the cage starts a chain of at most p_.swapSweepChain swaps that lowers the summed valence
  // defect (SweepSwap), each chain a step of its own (local fit and the steps' checks; refused
  // chains are undone), in face order, until a pass keeps nothing or after `passes` passes. The
  // paper swaps only in the 1-ring of a collapse's survivor, one swap at a time, so pairs of
  // singularities two or three edges apart stay. Returns the chains kept; -1: test mode found an
  // invalid state (res_.error).
  int SwapSweep(int passes);
  // The best swap of edge j of g: its variant and valence-defect change (false: none allowed).
  bool BestSwap(int g, int j, int* var, int* delta) const;
  // The corners of the two faces of interior edge j of g (the hexagon its swap rewires).
  std::vector<int> EdgeFaceCorners(int g, int j) const;
  // Applies, inside the running transaction, the best swap of edge j of g when it lowers the
  // valence defect, or when it leaves it unchanged (it moves a singularity), depth > 0 and a
  // LoweringChain of depth - 1 next to it follows; false: nothing applied, the mesh as it was.
  // `seeds` gets the corners of the faces the chain changed (the innermost swap's first).
  bool ChainFrom(int g, int j, int depth, std::vector<int>& seeds);
  // The first ChainFrom(depth) on an edge of a face around `around`, in mesh order (a
  // singularity moved to a partner and cancelled with it); false: none, the mesh as it was.
  bool LoweringChain(const std::vector<int>& around, int depth, std::vector<int>& seeds);
  // A chain of at most p_.swapSweepChain swaps that starts with the swap of edge j of g, applied
  // and checked (true: kept).
  bool SweepSwap(int g, int j);

  // ---- the pass (simplifier.cpp)
  // The caches of every element (projections, flip state, vertex points) on the initial mesh,
  // and the heap with every face's cheaper diagonal.
  void Initialize();

  // Test mode, after a committed step: the mesh's invariants and the step's caches.
  bool Validate(const QuadMesh::Invariants& inv);

  // Steps in cost order (§3.3; the M test when the pass has it) until the heap is empty, the
  // target is reached or the gate stops the pass (`cancelled`: the layout pass of an overlapped
  // count whose count undercut it). False: test mode found an invalid state (res_.error).
  bool Run(Progress& prog);

  // Final cleanup of normal disagreements that survived (pre-existing ones on noisy scans may
  // persist: a step only has to lower their count). Around each bad vertex / patch, extra
  // smoothing + re-interpolation rounds on a 2-ring; kept only if the region gets better.
  // Returns the number of regions improved.
  int FixFlips();

  int CountFlipped() const;
  int CountFlippedVertices() const;

 private:
  // 16 bytes (the heap holds ~10^6 entries on bunny00, many stale: memory traffic matters)
  struct Entry {
    float cost;
    int f;
    unsigned stampK;   ///< stamp << 1 | diagonal
    float otherCost;   ///< cost of the face's other diagonal (-1: none / already queued)
    int k() const { return int(stampK & 1u); }
    unsigned stamp() const { return stampK >> 1; }
    bool operator<(const Entry& o) const { return cost > o.cost; }  // min-heap
  };
  static Entry MakeEntry(double cost, int f, int k, unsigned stamp, double other) {
    return Entry{float(cost), f, (stamp << 1) | unsigned(k & 1), float(other)};
  }
  const TriData& in_;
  const TriData& start_;
  const EmbreeScene& scene_;
  const std::vector<double>& S_;
  const std::vector<double>& M_;
  const QuadSimplifyParams& p_;
  QuadSimplifyResult& res_;
  double diag_ = 1, maxDist_ = 1, tol_ = 1e-9;
  double maxM_ = 0;  ///< largest M-fitmap value (bounds the guard's ray length)
  /// LineHit's window: 0.5 % of the diagonal covers the limit surface's usual distance to the
  /// input during simplification (bunny00: the first ray settles 73 % of the queries)
  double window_ = 0;
  std::vector<Vec3> FN_;
  std::vector<char> pinned_;  // K vertex slots = start mesh vertex indices for the original vertices
  std::vector<FaceInfo> info_, newInfo_;
  std::vector<char> vok_, newVok_;
  std::vector<int> vhit_, newVhit_;
  std::vector<unsigned> wmarkOf_;
  std::vector<int> wIndex_;         ///< position of a vertex in the current step's W
  std::vector<Vec3> lfTargets_;     ///< see LocalFit
  std::vector<int> lfHit_;
  unsigned wmark_ = 0;
  mutable std::vector<Vec3> lim_;
  std::vector<Vec3> vp_;
  std::vector<unsigned> vpStamp_;
  std::vector<Vec3> vpc_;     ///< persistent vertex points (see RegionVertexPoint)
  std::vector<char> vpcOk_;
  long vpcStale_ = 0;         ///< test mode: cached vertex points found stale (must stay 0)
  long memoStale_ = 0;        ///< test mode: memo_ entries found stale (must stay 0)
  quad::QuadMemo memo_{K};    ///< centroids / neighbours during the checks of a step
  std::vector<quad::QuadMemo> threadMemos_;  ///< the same for check threads 1.. (thread 0: memo_)
  // this thread's memo during the parallel checks
  const quad::QuadMemo& ThreadMemo() const {
#ifdef _OPENMP
    const int t = omp_get_thread_num();
    if (t > 0 && t <= int(threadMemos_.size())) return threadMemos_[t - 1];
#endif
    return memo_;
  }
  unsigned vpEpoch_ = 0;
  // per-step check buffers (index = position in region_)
  std::vector<int> vpTodo_;  ///< corners whose vertex point this step computes
  std::vector<char> regionTouchesW_, devOk_;
  int checkThreads_ = 1;  ///< threads for a step's checks and projections (AdaptiveParallelism)
  long workUnits_ = 0;    ///< work of the steps of the current block (W, ring1(W) and faces checked)
  mutable std::vector<char> limOk_;
  mutable std::vector<signed char> vside_, fside_;  ///< see VSide / FSide
  std::vector<unsigned> stamp_;
  std::vector<unsigned> fmarkOf_, vmarkOf_;
  unsigned fmark_ = 0, vmark_ = 0;
  std::vector<int> region_, R1_;
  std::priority_queue<Entry> heap_;
};

}  // namespace simplify_internal
}  // namespace vcgext
