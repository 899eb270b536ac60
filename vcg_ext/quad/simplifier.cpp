/// \file simplifier.cpp
/// One simplification pass (Fitmaps §3.2–3.4): the Simplifier (collapses, doublets, swaps, local
/// fit and their checks, in cost order until the pass's halting) and SimplifyOnce around it.
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
#include "vcg_ext/quad/tri_to_quad.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext {
namespace simplify_internal {

using quad::OpResult;
using quad::QuadMesh;

namespace {

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
             const std::vector<double>& M, const QuadSimplifyParams& p, QuadSimplifyResult& res)
      : in_(in), start_(start), scene_(scene), S_(S), M_(M), p_(p), res_(res) {
    diag_ = BBoxDiagonal(in.V);
    maxDist_ = p.projectionPercent / 100.0 * diag_;
    window_ = 0.005 * diag_;
    for (double m : M) if (std::isfinite(m)) maxM_ = std::max(maxM_, m);
    tol_ = p.solveTolPercent / 100.0 * diag_;
    FN_ = FaceNormals(in);
    // sharp corners of the start mesh's boundary (turn > boundaryCornerAngleDeg) are pinned
    const std::vector<std::pair<int, int>> sseg = &start == &in ? scene.BoundaryEdges() : BoundaryHalfEdges(start);
    pinned_.assign(start.V.size(), 0);
    std::vector<int> bnext(start.V.size(), -1), bprev(start.V.size(), -1);
    for (auto& [a, b] : sseg) { bnext[a] = b; bprev[b] = a; }
    const double cmin = std::cos(p.boundaryCornerAngleDeg * M_PI / 180.0);
    for (size_t v = 0; v < start.V.size(); ++v) {
      if (bnext[v] < 0 || bprev[v] < 0) continue;
      Vec3 e1 = start.V[v] - start.V[bprev[v]], e2 = start.V[bnext[v]] - start.V[v];
      if (e1.dot(e2) < cmin * e1.norm() * e2.norm()) pinned_[v] = 1;
    }
  }
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
  quad::InterpolationStats Reinterpolate() {
    std::vector<Vec3> targets(K.NumVertexSlots(), Vec3::Zero());
    std::vector<int> alive;
    for (int v = 0; v < K.NumVertexSlots(); ++v)
      if (K.VertAlive(v)) alive.push_back(v);
#pragma omp parallel for schedule(dynamic, 64)
    for (long i = 0; i < long(alive.size()); ++i) targets[alive[i]] = VertexTarget(alive[i]);
    return quad::SolveInterpolationGlobal(K, targets, tol_);
  }

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

  // After LocalFit: lfTargets_[i] / lfHit_[i] = the last round's target of W[i] and the input
  // triangle it lies on (-1: not a projection along the normal).
  void LocalFit(const std::vector<int>& W, int rounds = -1) {
    std::vector<Vec3> newP(W.size());
    std::vector<Vec3>& targets = lfTargets_;
    targets.resize(W.size());
    lfHit_.assign(W.size(), -1);
    std::vector<quad::Wedge> fan;
    if (rounds < 0) rounds = p_.fitRounds;
    for (int round = 0; round < rounds; ++round) {
      for (size_t i = 0; i < W.size(); ++i) {
        int v = W[i];
        Vec3 avg = Vec3::Zero();
        if (Pinned(v)) {
          avg = K.P[v];
        } else if (K.IsBoundary(v)) {
          avg = K.Fan(v, fan) ? Vec3(0.5 * (K.P[fan.front().p] + K.P[fan.back().n])) : K.P[v];
        } else {
          for (int g : K.VF(v)) avg += K.Centroid(g);
          avg /= double(K.VF(v).size());
        }
        newP[i] = (1.0 - p_.smoothingWeight) * K.P[v] + p_.smoothingWeight * avg;
      }
      for (size_t i = 0; i < W.size(); ++i) K.MoveVertex(W[i], newP[i]);
      // projections (read-only but for each vertex's own side hint): in parallel
#pragma omp parallel for num_threads(checkThreads_) if (checkThreads_ > 1 && W.size() >= 8) schedule(dynamic, 2)
      for (long i = 0; i < long(W.size()); ++i) targets[i] = VertexTarget(W[i], &lfHit_[i]);
      quad::SolveInterpolationLocal(K, W, targets, tol_, p_.localSolveIterations);
    }
  }

  // Test mode: every memoized entry the step's checks used must still be exact.
  void CountStaleMemos() {
    if (!p_.validateEveryOperation) return;
    memoStale_ += memo_.CountStale();
    for (const auto& m : threadMemos_) memoStale_ += m.CountStale();
  }
  // Undoes the step being checked (test mode: after verifying the memos the checks used).
  int Refuse(int code) {
    CountStaleMemos();
    K.Rollback();
    return code;
  }

  // What a step's operators did (counted in the result when the step is committed).
  struct StepCounts {
    int doublets = 0, swaps = 0, corners = 0;
  };

  // Immediate doublet removal after a collapse (cascading from the vertices in dq); boundary
  // corners on flat stretches of the boundary are removed likewise (RemoveBoundaryCorner), which
  // is what coarsens open boundaries. False: an operator failed (the step must be rolled back).
  bool RemoveDoubletsAndCorners(std::vector<int> dq, std::vector<int>& affected, StepCounts& n) {
    int guard = 0;
    while (!dq.empty() && ++guard < 1000) {
      int v = dq.back();
      dq.pop_back();
      if (!K.VertAlive(v) || K.VF(v).size() > 2) continue;
      if (!K.IsBoundary(v) && K.VF(v).size() == 2) {
        int f1 = K.VF(v)[0], k1 = K.CornerOf(f1, v);
        int na = K.F[f1][(k1 + 1) & 3], nb = K.F[f1][(k1 + 3) & 3];
        if (K.RemoveDoublet(v) != OpResult::Ok) return false;
        ++n.doublets;
        for (int x : {na, nb}) { dq.push_back(x); affected.push_back(x); }
      } else if (K.IsBoundary(v) && K.VF(v).size() == 1 && p_.boundaryCornerAngleDeg > 0) {
        int f1 = K.VF(v)[0], k1 = K.CornerOf(f1, v);
        int c = K.F[f1][(k1 + 1) & 3], o = K.F[f1][(k1 + 2) & 3], a = K.F[f1][(k1 + 3) & 3];
        Vec3 e1 = K.P[v] - K.P[a], e2 = K.P[c] - K.P[v];
        double cosTurn = e1.dot(e2) / std::max(1e-300, e1.norm() * e2.norm());
        if (cosTurn < std::cos(p_.boundaryCornerAngleDeg * M_PI / 180.0)) continue;
        // pinned input corners survive (index and position)
        if (Pinned(v) || (Pinned(a) && Pinned(c))) continue;
        int keep = Pinned(a) ? 1 : Pinned(c) ? 2 : 0;
        int surv = -1;
        if (K.RemoveBoundaryCorner(v, &surv, keep) != OpResult::Ok) continue;  // allowed to stay
        ++n.corners;
        for (int x : {surv, o}) { dq.push_back(x); affected.push_back(x); }
      }
    }
    return true;
  }

  // Edge swaps in the 1-ring of the collapsed element's survivor s, while some strictly lowers
  // the valence energy (at most 4 passes).
  void SwapAround(int s, std::vector<int>& affected, StepCounts& n) {
    for (int pass = 0; pass < 4; ++pass) {
      bool any = false;
      std::vector<int> faces = K.VF(s);
      for (int g : faces) {
        for (int j = 0; j < 4; ++j) {
          if (!K.FaceAlive(g)) break;
          int bestVar = -1, best = 0;
          if (!BestSwap(g, j, &bestVar, &best) || best >= 0) continue;
          const std::vector<int> hex = EdgeFaceCorners(g, j);
          if (K.SwapEdge(g, j, bestVar) == OpResult::Ok) {
            ++n.swaps;
            any = true;
            affected.insert(affected.end(), hex.begin(), hex.end());
          }
        }
      }
      if (!any) break;
    }
  }

  // The elements whose limit a step changed, for its flip test: R1_ = the vertices of ring1(W)
  // (their limit normal depends on their 1-ring) and region_ = the faces incident to them (centre
  // limit depends on the corners' 1-rings); vpTodo_ = the corners whose vertex points must be
  // computed in this step (shared caches). Sequential.
  void CollectCheckRegion(const std::vector<int>& W) {
    ++wmark_;
    for (size_t i = 0; i < W.size(); ++i) { wmarkOf_[W[i]] = wmark_; wIndex_[W[i]] = int(i); }
    CollectRing(W, R1_);
    ++fmark_;
    region_.clear();
    for (int v : R1_)
      for (int g : K.VF(v))
        if (fmarkOf_[g] != fmark_) { fmarkOf_[g] = fmark_; region_.push_back(g); }
    workUnits_ += long(R1_.size() + region_.size());
    newVok_.resize(R1_.size());
    newVhit_.resize(R1_.size());
    newInfo_.resize(region_.size());
    regionTouchesW_.resize(region_.size());
    devOk_.resize(region_.size());
    ++vpEpoch_;
    vpTodo_.clear();
    for (size_t i = 0; i < region_.size(); ++i) {
      const int g = region_[i];
      bool touchesW = false;
      for (int k = 0; k < 4; ++k) {
        int x = K.F[g][k];
        touchesW |= vmarkOfW(x);
        if (ClaimVertexPoint(x)) vpTodo_.push_back(x);
      }
      regionTouchesW_[i] = touchesW;
    }
  }

  // The checks of a step on CollectCheckRegion's elements, into newVok_ / newVhit_ / newInfo_ /
  // devOk_. They only read shared state (each element writes its own result slots and its own
  // side hint — a hint picks which ray answers a later query, so at most the rounding of that
  // answer, and one element writes it —; each thread has its own memo), so they run in parallel
  // (checkThreads_). Every check runs; Verdict picks the first failure in the sequential order,
  // exactly as the sequential loop would.
  void RunChecks() {
#pragma omp parallel num_threads(checkThreads_) if (checkThreads_ > 1 && R1_.size() + region_.size() >= 16)
    {
      const quad::QuadMemo& memo = ThreadMemo();
#pragma omp for schedule(dynamic, 8)
      for (long i = 0; i < long(vpTodo_.size()); ++i) ComputeVertexPoint(vpTodo_[i], memo);
#pragma omp for schedule(dynamic, 4) nowait
      for (long i = 0; i < long(R1_.size()); ++i) {
        const int v = R1_[i];
        newVok_[i] = vmarkOfW(v) ? VertexOkAfterFit(v, lfTargets_[wIndex_[v]], lfHit_[wIndex_[v]], &newVhit_[i])
                                 : VertexOkFast(v, &newVhit_[i]);
      }
#pragma omp for schedule(dynamic, 2)
      for (long i = 0; i < long(region_.size()); ++i) {
        const int g = region_[i];
        Vec3 vp[4];
        for (int k = 0; k < 4; ++k) vp[k] = RegionVertexPoint(K.F[g][k]);
        bool done = false;
        if (!regionTouchesW_[i] && info_[g].ok && info_[g].hit >= 0) {
          FaceInfo fi = info_[g];
          Vec3 n;
          if (quad::FaceCentreLimit(memo, g, vp, &fi.c, &n) && FN_[fi.hit].dot(n) > 0) { newInfo_[i] = fi; done = true; }
        }
        if (!done) newInfo_[i] = EvalFace(g, vp, &memo);
        // the guard (not needed when this face's flip check already refuses the step)
        const bool guard = regionTouchesW_[i] && p_.deviationFactor > 0 && !(info_[g].ok && !newInfo_[i].ok);
        devOk_[i] = !guard || FaceDeviationOk(g, vp, newInfo_[i], memo);
      }
    }
    if (p_.validateEveryOperation)  // the persistent vertex points used must still be exact
      for (int g : region_)
        for (int x : K.F[g])
          if (vmarkOf_[x] != vmark_ && !(vpc_[x] == quad::VertexPoint(K, x))) ++vpcStale_;
  }

  // The checks' verdict: 0 = pass; 2 = an element that agreed with the input does not now (flip);
  // 3 = the geometric guard (the first failure in the sequential order gives the code).
  int Verdict() const {
    for (size_t i = 0; i < R1_.size(); ++i)
      if (vok_[R1_[i]] && !newVok_[i]) return 2;
    for (size_t i = 0; i < region_.size(); ++i) {
      if (info_[region_[i]].ok && !newInfo_[i].ok) return 2;
      if (!devOk_[i]) return 3;
    }
    return 0;
  }

  // The committed mesh and the caches of the checked elements; their costs re-queued.
  void CommitCaches() {
    K.Commit();
    for (int v : R1_) vpcOk_[v] = 0;  // their committed vertex points changed
    for (int g : region_)
      for (int j = 0; j < 4; ++j) limOk_[K.F[g][j]] = 0;  // all of ring1(W)
    for (size_t i = 0; i < region_.size(); ++i) info_[region_[i]] = newInfo_[i];
    for (size_t i = 0; i < R1_.size(); ++i) { vok_[R1_[i]] = newVok_[i]; vhit_[R1_[i]] = newVhit_[i]; }
    // re-queue faces whose cost may have changed
    for (int g : region_) Push(g);
  }

  // Checks the pending operation on the moved ring W (local fit, then the step's checks):
  // 0 = kept (committed caches), else the refusal code (rolled back).
  int FitCheckCommit(const std::vector<int>& W) {
    LocalFit(W);
    memo_.Reset();  // positions and connectivity are frozen from here to Commit/Rollback
    for (auto& m : threadMemos_) m.Reset();
    CollectCheckRegion(W);
    RunChecks();
    if (const int code = Verdict()) return Refuse(code);
    CountStaleMemos();
    CommitCaches();
    return 0;
  }

  // Beyond the paper (issue 13, docs/quad.md "Swap sweep"): after the last collapse, every edge of
  // the cage starts a chain of at most p_.swapSweepChain swaps that lowers the summed valence
  // defect (SweepSwap), each chain a step of its own (local fit and the steps' checks; refused
  // chains are undone), in face order, until a pass keeps nothing or after `passes` passes. The
  // paper swaps only in the 1-ring of a collapse's survivor, one swap at a time, so pairs of
  // singularities two or three edges apart stay. Returns the chains kept; -1: test mode found an
  // invalid state (res_.error).
  int SwapSweep(int passes) {
    QuadMesh::Invariants inv;
    if (p_.validateEveryOperation) inv = K.ComputeInvariants();
    int kept = 0;
    for (int pass = 0; pass < passes; ++pass) {
      int keptNow = 0;
      for (int g = 0; g < K.NumFaceSlots(); ++g)
        for (int j = 0; j < 4 && K.FaceAlive(g); ++j) {
          if (!SweepSwap(g, j)) continue;
          ++keptNow;
          if (p_.validateEveryOperation && !Validate(inv)) return -1;
        }
      kept += keptNow;
      if (keptNow == 0) break;
    }
    return kept;
  }
  // The best swap of edge j of g: its variant and valence-defect change (false: none allowed).
  bool BestSwap(int g, int j, int* var, int* delta) const {
    *var = -1;
    for (int v = 0; v < 2; ++v) {
      int d;
      if (K.SwapEnergyDelta(g, j, v, &d) && (*var < 0 || d < *delta)) { *delta = d; *var = v; }
    }
    return *var >= 0;
  }
  // The corners of the two faces of interior edge j of g (the hexagon its swap rewires).
  std::vector<int> EdgeFaceCorners(int g, int j) const {
    const int h = K.AcrossEdge(g, j);
    std::vector<int> c(K.F[g].begin(), K.F[g].end());
    c.insert(c.end(), K.F[h].begin(), K.F[h].end());
    return c;
  }
  // Applies, inside the running transaction, the best swap of edge j of g when it lowers the
  // valence defect, or when it leaves it unchanged (it moves a singularity), depth > 0 and a
  // LoweringChain of depth - 1 next to it follows; false: nothing applied, the mesh as it was.
  // `seeds` gets the corners of the faces the chain changed (the innermost swap's first).
  bool ChainFrom(int g, int j, int depth, std::vector<int>& seeds) {
    int var = -1, delta = 0;
    if (!BestSwap(g, j, &var, &delta) || delta > 0 || (delta == 0 && depth <= 0)) return false;
    const std::vector<int> hex = EdgeFaceCorners(g, j);
    const QuadMesh::Mark mark = K.JournalMark();
    if (K.SwapEdge(g, j, var) != OpResult::Ok) return false;  // (a refused operator undoes itself)
    if (delta < 0 || LoweringChain(hex, depth - 1, seeds)) {
      seeds.insert(seeds.end(), hex.begin(), hex.end());
      return true;
    }
    K.UndoTo(mark);
    return false;
  }
  // The first ChainFrom(depth) on an edge of a face around `around`, in mesh order (a
  // singularity moved to a partner and cancelled with it); false: none, the mesh as it was.
  bool LoweringChain(const std::vector<int>& around, int depth, std::vector<int>& seeds) {
    for (int x : around) {
      if (!K.VertAlive(x)) continue;
      const std::vector<int> faces = K.VF(x);
      for (int g : faces)
        for (int j = 0; j < 4 && K.FaceAlive(g); ++j)
          if (ChainFrom(g, j, depth, seeds)) return true;
    }
    return false;
  }
  // A chain of at most p_.swapSweepChain swaps that starts with the swap of edge j of g, applied
  // and checked (true: kept).
  bool SweepSwap(int g, int j) {
    if (K.AcrossEdge(g, j) < 0) return false;
    // the start's corners first: the order of the local fit's ring (ChainFrom adds them again)
    std::vector<int> seeds = EdgeFaceCorners(g, j);
    K.Begin();
    if (!ChainFrom(g, j, p_.swapSweepChain - 1, seeds)) {
      K.Rollback();
      return false;
    }
    std::vector<int> W;
    CollectRing(seeds, W);
    return FitCheckCommit(W) == 0;
  }
  // One simplification step: collapse + doublets + swaps + local fit, or nothing.
  // Returns 0 = done, 1 = topology refusal, 2 = flip refusal, 3 = geometric guard refusal.
  int Step(int f, int k) {
    K.Begin();
    int b = K.F[f][k + 1], d = K.F[f][(k + 3) & 3];
    int s = -1;
    OpResult r = K.CollapseDiagonal(f, k, &s);
    if (r != OpResult::Ok) { K.Rollback(); return 1; }
    std::vector<int> affected{s, b, d};
    StepCounts n;
    if (!RemoveDoubletsAndCorners({b, d, s}, affected, n)) { K.Rollback(); return 1; }
    if (p_.edgeSwaps && K.VertAlive(s)) SwapAround(s, affected, n);
    std::vector<int> W;
    CollectRing(affected, W);
    workUnits_ += long(W.size());  // the step's size (with the checked elements below)
    if (const int code = FitCheckCommit(W)) return code;
    res_.collapses++;
    res_.doublets += n.doublets;
    res_.swaps += n.swaps;
    res_.boundaryCorners += n.corners;
    return 0;
  }

  // The caches of every element (projections, flip state, vertex points) on the initial mesh,
  // and the heap with every face's cheaper diagonal.
  void Initialize() {
    threadMemos_.assign(checkThreads_ - 1, quad::QuadMemo(K));
    const int nf = K.NumFaceSlots(), nv = K.NumVertexSlots();
    info_.assign(nf, FaceInfo());
    vside_.assign(nv, 1);
    fside_.assign(nf, 1);
    stamp_.assign(nf, 0);
    fmarkOf_.assign(nf, 0);
    vmarkOf_.assign(nv, 0);
    std::vector<int> alive;
    for (int f = 0; f < nf; ++f)
      if (K.FaceAlive(f)) alive.push_back(f);
#pragma omp parallel for schedule(dynamic, 256)
    for (long i = 0; i < long(alive.size()); ++i) info_[alive[i]] = EvalFace(alive[i]);
    vok_.assign(nv, 1);
    vhit_.assign(nv, -1);
    wmarkOf_.assign(nv, 0);
    wIndex_.assign(nv, -1);
    lim_.assign(nv, Vec3::Zero());
    vp_.assign(nv, Vec3::Zero());
    vpStamp_.assign(nv, 0);
    vpc_.assign(nv, Vec3::Zero());
    vpcOk_.assign(nv, 0);
    limOk_.assign(nv, 0);
#pragma omp parallel for schedule(dynamic, 256)
    for (int v = 0; v < nv; ++v) vok_[v] = VertexOk(v, &vhit_[v]) ? 1 : 0;
    for (int f : alive) res_.initialFlippedPatches += info_[f].ok ? 0 : 1;
    for (int v = 0; v < nv; ++v) res_.initialFlippedVertices += vok_[v] ? 0 : 1;
    for (int f : alive) Push(f);
  }

  // Test mode, after a committed step: the mesh's invariants and the step's caches.
  bool Validate(const QuadMesh::Invariants& inv) {
    std::string err = K.Check(&inv);
    if (err.empty() && vpcStale_ > 0) err = std::to_string(vpcStale_) + " stale cached vertex points";
    if (err.empty() && memoStale_ > 0) err = std::to_string(memoStale_) + " stale memoized centroids/neighbours";
    if (err.empty()) return true;
    res_.error = "internal error: invalid mesh after collapse " + std::to_string(res_.collapses) + ": " + err;
    return false;
  }

  // Steps in cost order (§3.3; the M test when the pass has it) until the heap is empty, the
  // target is reached or the gate stops the pass (`cancelled`: the layout pass of an overlapped
  // count whose count undercut it). False: test mode found an invalid state (res_.error).
  bool Run(Progress& prog) {
#ifdef _OPENMP
    // at most 2: a step checks a few dozen to a few hundred elements, and 2 is what was measured
    checkThreads_ = std::clamp(omp_get_max_threads(), 1, 2);
#endif
    Initialize();
    QuadMesh::Invariants inv;
    if (p_.validateEveryOperation) inv = K.ComputeInvariants();
    const int initial = K.NumFaces();
    const int maxThreads = checkThreads_;
    using PC = QuadSimplifyParams::ParallelChecks;
    AdaptiveParallelism mode(maxThreads > 1 && p_.parallelChecks == PC::Adaptive);
    int blockSteps = 0, parallelSteps = 0, steps = 0;
    auto blockStart = std::chrono::steady_clock::now();
    // serial checks while the count pass holds the other core (gate target not known yet)
    auto threadsFor = [&](bool parallel) {
      if (gate && gate->Target() == 0) return 1;
      return p_.parallelChecks == PC::Always || parallel ? maxThreads : 1;
    };
    checkThreads_ = threadsFor(mode.Parallel());
    while (!heap_.empty()) {
      if (publishTo) publishTo->Publish(K.NumFaces());
      if (gate) {
        const int t = gate->Admit(K.NumFaces(), &gateWait);
        if (t < 0) { cancelled = true; return true; }
        if (t > 0 && K.NumFaces() <= t) break;
      }
      if (p_.targetPatches > 0 && K.NumFaces() <= p_.targetPatches) break;
      Entry e = heap_.top();
      heap_.pop();
      if (!K.FaceAlive(e.f) || e.stamp() != (stamp_[e.f] & 0x7fffffffu)) continue;
      if (p_.useMFitmap && !MTest(e.f, e.k())) {
        ++res_.rejectedByM;
        if (e.otherCost >= 0) heap_.push(MakeEntry(e.otherCost, e.f, 1 - e.k(), e.stamp(), -1.0));
        continue;
      }
      int r = Step(e.f, e.k());
      ++steps;
      parallelSteps += checkThreads_ > 1 ? 1 : 0;
      if (gate && gate->Target() == 0) {
        // the count pass holds the other core: serial checks, and no block is measured (a block
        // timed now would tell AdaptiveParallelism nothing about the time after the count)
        blockStart = std::chrono::steady_clock::now();
        workUnits_ = 0;
        blockSteps = 0;
      } else if (checkThreads_ == 1 && gate && mode.Parallel() && p_.parallelChecks != PC::Never) {
        checkThreads_ = threadsFor(true);  // the count just ended: back to the mode's choice
      } else if (++blockSteps >= mode.BlockSteps()) {
        const auto now = std::chrono::steady_clock::now();
        checkThreads_ = threadsFor(
            mode.EndBlock(std::chrono::duration<double>(now - blockStart).count() / std::max<long>(1, workUnits_)));
        blockStart = now;
        workUnits_ = 0;
        blockSteps = 0;
      }
      if (r == 1) ++res_.rejectedTopology;
      if (r == 2) ++res_.rejectedFlip;
      if (r == 3) ++res_.rejectedDeviation;
      if (r != 0 && e.otherCost >= 0) heap_.push(MakeEntry(e.otherCost, e.f, 1 - e.k(), e.stamp(), -1.0));
      if (p_.validateEveryOperation && r == 0 && !Validate(inv)) return false;
      prog(100.0 * (initial - K.NumFaces()) / std::max(1, initial), "Quad simplification");
    }
    res_.parallelStepShare = steps > 0 ? double(parallelSteps) / steps : 0.0;
    return true;
  }

  // Final cleanup of normal disagreements that survived (pre-existing ones on noisy scans may
  // persist: a step only has to lower their count). Around each bad vertex / patch, extra
  // smoothing + re-interpolation rounds on a 2-ring; kept only if the region gets better.
  // Returns the number of regions improved.
  int FixFlips() {
    int improved = 0;
    std::vector<int> seeds;
    for (int v = 0; v < K.NumVertexSlots(); ++v)
      if (K.VertAlive(v) && !VertexOk(v)) seeds.push_back(v);
    for (int f = 0; f < K.NumFaceSlots(); ++f)
      if (K.FaceAlive(f) && !EvalFace(f).ok) seeds.push_back(K.F[f][0]);
    std::vector<int> W1, W;
    for (int seed : seeds) {
      for (int rounds : {2, 4, 8}) {
        CollectRing({seed}, W1);
        CollectRing(W1, W);
        auto count = [&]() {
          int bad = 0;
          ++fmark_;
          for (int v : W) {
            bad += VertexOk(v) ? 0 : 1;
            for (int g : K.VF(v))
              if (fmarkOf_[g] != fmark_) { fmarkOf_[g] = fmark_; bad += EvalFace(g).ok ? 0 : 1; }
          }
          return bad;
        };
        int before = count();
        if (before == 0) break;
        K.Begin();
        LocalFit(W, rounds);
        int after = count();
        if (after < before) { K.Commit(); ++improved; if (after == 0) break; }
        else K.Rollback();
      }
    }
    return improved;
  }

  int CountFlipped() const {
    int bad = 0;
    for (int f = 0; f < K.NumFaceSlots(); ++f)
      if (K.FaceAlive(f) && !EvalFace(f).ok) ++bad;
    return bad;
  }
  int CountFlippedVertices() const {
    int bad = 0;
    for (int v = 0; v < K.NumVertexSlots(); ++v)
      if (K.VertAlive(v) && !VertexOk(v)) ++bad;
    return bad;
  }

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

}  // namespace

void AppendMessage(std::string& message, const std::string& note) {
  message += (message.empty() ? "" : "; ") + note;
}

namespace {
// Step 1 of SimplifyOnce (§3.2): the initial quads, given (a pure-quad layer) or paired from the
// start's triangles. False (res.error set) when they cannot be had.
bool InitialQuads(const TriData& input, const TriData& start, const QuadSimplifyParams& params,
                  const std::vector<Quad>* initialQuads, QuadData& q0, QuadSimplifyResult& res) {
  const int nv = int(input.V.size());
  if (initialQuads && !initialQuads->empty()) {
    q0.V = input.V;
    q0.F = *initialQuads;
    for (const Quad& q : q0.F)
      for (int x : q)
        if (x < 0 || x >= nv) { res.error = "initial quad references vertex " + std::to_string(x) + " out of range"; return false; }
    res.triToQuadPath = quad::TriToQuadPath::AlreadyQuads;
    return true;
  }
  quad::TriToQuadResult tq = quad::TriToQuad(start, params.triToQuad);
  if (!tq.error.empty()) { res.error = "tri-to-quad: " + tq.error; return false; }
  q0 = std::move(tq.quads);
  res.triToQuadPath = tq.path;
  return true;
}

// The final checks of SimplifyOnce: flipped patches fixed and counted, and the final
// re-interpolation, kept only if it does not add normal disagreements (it moves every control point).
void FinalChecks(const QuadSimplifyParams& params, Simplifier& sim, QuadSimplifyResult& res) {
  if (res.collapses > 0) sim.FixFlips();
  res.flippedPatches = sim.CountFlipped();
  res.flippedVertices = sim.CountFlippedVertices();
  if (!params.finalReinterpolation || res.collapses == 0) return;
  std::vector<Vec3> before = sim.K.P;
  sim.Reinterpolate();
  int fp = sim.CountFlipped(), fv = sim.CountFlippedVertices();
  if (fp + fv > res.flippedPatches + res.flippedVertices) {
    sim.K.P = before;
    AppendMessage(res.message, "final re-interpolation skipped (it would flip patches)");
  } else {
    res.flippedPatches = fp;
    res.flippedVertices = fv;
  }
}
}  // namespace

QuadSimplifyResult SimplifyOnce(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress prog, const std::vector<Quad>* initialQuads,
                                quad::LayoutGate* gate, bool* cancelled, double* gateWait,
                                quad::LayoutGate* publishTo) {
  QuadSimplifyResult res;
  const auto t0 = Clock::now();
  prog(0, "Tri-to-quad", true);
  // 1. initial quads (§3.2)
  QuadData q0;
  if (!InitialQuads(input, start, params, initialQuads, q0, res)) return res;
  res.secondsTriToQuad = Since(t0);
  // 2. interpolating control points (§3.2)
  auto t1 = Clock::now();
  QuadSimplifyResult& r = res;
  Simplifier sim(input, start, scene, S, M, params, r);
  sim.K = QuadMesh(q0.V, q0.F);
  {
    std::string err = sim.K.Check();
    if (!err.empty()) { res.error = "initial quad mesh invalid: " + err; return res; }
  }
  res.initialPatches = sim.K.NumFaces();
  const double tol = params.solveTolPercent / 100.0 * BBoxDiagonal(input.V);
  quad::InterpolationStats gs = quad::SolveInterpolationGlobal(sim.K, q0.V, tol);
  res.initialSolveResidual = gs.maxResidual;
  res.initialSolveIterations = gs.iterations;
  res.secondsInitialFit = Since(t1);
  prog(10, "Quad simplification", true);
  // 3-4. simplification with local fit (§3.3-3.4)
  auto t2 = Clock::now();
  if (sim.K.NumFaces() <= std::max(6, params.targetPatches)) {
    res.message = "mesh too small to simplify (" + std::to_string(sim.K.NumFaces()) + " quads): returning its pure-quad mesh";
  } else {
    Progress sub = prog.Sub(10, 95);
    sim.gate = gate;
    sim.publishTo = publishTo;
    const bool ok = sim.Run(sub);
    if (gateWait) *gateWait = sim.gateWait;
    if (sim.cancelled) {
      if (cancelled) *cancelled = true;
      return res;
    }
    if (!ok) return res;
    if (res.collapses == 0) res.message = "no feasible collapse: returning the initial pure-quad mesh";
  }
  prog(96, "Quad simplification: final checks", true);
  FinalChecks(params, sim, res);
  res.secondsSimplify = Since(t2);
  res.quads = sim.K.ToQuadData();
  res.patches = sim.K.NumFaces();
  res.valenceHistogram = sim.K.ValenceHistogram(&res.irregularVertices);
  res.secondsTotal = Since(t0);
  return res;
}

void SweepCage(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
               const std::vector<double>& M, const QuadSimplifyParams& params, QuadSimplifyResult& r) {
  if (!params.edgeSwaps || params.swapSweepChain <= 0 || !r.error.empty() || r.quads.F.empty()) return;
  const auto t0 = Clock::now();
  // the cage as triangles, the Simplifier's start: its boundary corners are the ones pinned
  const TriData start = SplitQuads(r.quads);
  QuadSimplifyResult scratch;
  Simplifier sim(input, start, scene, S, M, params, scratch);
  sim.K = QuadMesh(r.quads.V, r.quads.F);
  sim.Initialize();  // the checks' caches, on one thread: a chain's checks are a few dozen elements
  r.sweepSwaps = sim.SwapSweep(4);  // at most 4 passes (bunny00: the second keeps one chain, the third none)
  if (r.sweepSwaps < 0) {
    r.error = scratch.error;
    return;
  }
  if (r.sweepSwaps > 0) {
    r.quads = sim.K.ToQuadData();
    r.patches = sim.K.NumFaces();
    r.valenceHistogram = sim.K.ValenceHistogram(&r.irregularVertices);
    r.flippedPatches = sim.CountFlipped();
    r.flippedVertices = sim.CountFlippedVertices();
  }
  const double seconds = Since(t0);
  r.secondsSimplify += seconds;
  r.secondsTotal += seconds;
}

}  // namespace simplify_internal
}  // namespace vcgext
