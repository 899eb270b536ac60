#include "vcg_ext/quad/quad_simplify.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <mutex>
#include <queue>
#include <thread>
#include <unordered_map>

#include "vcg_ext/core/decimate.h"
#include "vcg_ext/core/progress.h"
#include "vcg_ext/fit/cc_fit.h"
#include "vcg_ext/quad/cc_limit.h"
#include "vcg_ext/quad/layout_gate.h"
#include "vcg_ext/quad/quad_mesh.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext {

using quad::OpResult;
using quad::QuadMesh;

void CountNonManifold(const TriData& m, int* nmEdges, int* nmVerts) {
  std::unordered_map<std::uint64_t, int> und, dir;
  und.reserve(m.F.size() * 2);
  dir.reserve(m.F.size() * 4);
  auto key = [](int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); };
  for (const auto& f : m.F)
    for (int k = 0; k < 3; ++k) {
      int a = f[k], b = f[(k + 1) % 3];
      ++und[key(std::min(a, b), std::max(a, b))];
      ++dir[key(a, b)];
    }
  int e = 0;
  for (auto& [k, c] : und) {
    int a = int(k >> 32), b = int(k & 0xffffffffu);
    if (c > 2 || dir[key(a, b)] > 1 || dir[key(b, a)] > 1) ++e;
  }
  // vertices: the fan of incident triangles must be one chain/cycle
  Adjacency vfa = VertexFaceAdjacency(m.F, int(m.V.size()));
  int nv = 0;
  std::vector<std::pair<int, int>> w;  // (next, prev) per incident triangle
  for (int v = 0; v < int(m.V.size()); ++v) {
    w.clear();
    for (const int* it = vfa.Begin(v); it != vfa.End(v); ++it) {
      const Tri& t = m.F[*it];
      int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
      w.push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
    }
    const int n = int(w.size());
    if (n == 0) continue;
    bool bad = false;
    int starts = 0, start = 0;
    for (int i = 0; i < n && !bad; ++i) {
      bool matched = false;
      for (int j = 0; j < n; ++j) {
        if (j != i && (w[j].first == w[i].first || w[j].second == w[i].second)) bad = true;
        if (w[j].first == w[i].second) matched = true;
      }
      if (!matched) { ++starts; start = i; }
    }
    if (!bad && starts <= 1) {
      int cur = start, count = 1;
      while (count < n) {
        int nxt = -1;
        for (int j = 0; j < n; ++j)
          if (w[j].second == w[cur].first) { nxt = j; break; }
        if (nxt < 0 || nxt == start) break;
        cur = nxt;
        ++count;
      }
      bad = count != n;
    } else {
      bad = true;
    }
    if (bad) ++nv;
  }
  if (nmEdges) *nmEdges = e;
  if (nmVerts) *nmVerts = nv;
}

bool AdaptiveParallelism::EndBlock(double secondsPerUnit) {
  ++blocks_;
  parallelBlocks_ += par_ ? 1 : 0;
  last_[par_] = secondsPerUnit;
  if (!allowed_) return par_ = false;
  const double other = last_[!par_];
  if (probing_ || confirming_) {  // the block just measured tried this mode (probe, then confirmation)
    const bool wasProbe = probing_;
    probing_ = confirming_ = false;
    sinceProbe_ = 0;
    // a probe must win clearly (block times are noisy); a confirmation only has to be faster
    if (secondsPerUnit < (wasProbe ? 0.85 : 1.0) * other) {
      // a short probe must be confirmed by one regular
      // block: under load a short parallel probe often runs before the other thread is
      // preempted, and looks fast (measured on bunny00 with a busy core: probes 1.0-1.1 us per
      // unit, the regular parallel blocks after them 2.1-2.3, serial 1.7)
      if (wasProbe && par_) confirming_ = true;
      else probe_ = minProbe_;
    } else {
      probe_ = std::min(2 * probe_, maxProbe_);
      Switch(false);
    }
    return par_;
  }
  if (other < 0 || ++sinceProbe_ >= probe_) Switch(true);      // never measured / time to probe
  else if (secondsPerUnit > 1.5 * other) {                      // clearly slower now (load changed):
    Switch(false);
    probe_ = minProbe_;  // the backoff of the old mode's probes does not apply to the new one
  }
  return par_;
}

void AdaptiveParallelism::Switch(bool probe) {
  par_ = !par_;
  probing_ = probe;
  sinceProbe_ = 0;
  ++switches_;
}

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

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
    // input boundary segments (half-edges without twin)
    bseg_ = BoundaryHalfEdges(in);
    // sharp corners of the start mesh's boundary (turn > boundaryCornerAngleDeg) are pinned
    const std::vector<std::pair<int, int>> sseg = &start == &in ? bseg_ : BoundaryHalfEdges(start);
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
    double best = std::numeric_limits<double>::infinity();
    Vec3 q = p;
    for (auto& [a, b] : bseg_) {
      const Vec3 &A = in_.V[a], &B = in_.V[b];
      Vec3 d = B - A;
      double l2 = d.squaredNorm();
      double t = l2 > 0 ? std::clamp((p - A).dot(d) / l2, 0.0, 1.0) : 0.0;
      Vec3 x = A + t * d;
      double dd = (x - p).squaredNorm();
      if (dd < best) { best = dd; q = x; }
    }
    return q;
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

  // One simplification step: collapse + doublets + swaps + local fit, or nothing.
  // Returns 0 = done, 1 = topology refusal, 2 = flip refusal, 3 = geometric guard refusal.
  int Step(int f, int k) {
    K.Begin();
    int b = K.F[f][k + 1], d = K.F[f][(k + 3) & 3];
    int s = -1;
    OpResult r = K.CollapseDiagonal(f, k, &s);
    if (r != OpResult::Ok) { K.Rollback(); return 1; }
    std::vector<int> affected{s, b, d};
    int doublets = 0, swaps = 0, corners = 0;
    // immediate doublet removal (cascading); boundary corners on flat stretches of the boundary
    // are removed likewise (RemoveBoundaryCorner), which is what coarsens open boundaries
    std::vector<int> dq{b, d, s};
    int guard = 0;
    while (!dq.empty() && ++guard < 1000) {
      int v = dq.back();
      dq.pop_back();
      if (!K.VertAlive(v) || K.VF(v).size() > 2) continue;
      if (!K.IsBoundary(v) && K.VF(v).size() == 2) {
        int f1 = K.VF(v)[0], k1 = K.CornerOf(f1, v);
        int na = K.F[f1][(k1 + 1) & 3], nb = K.F[f1][(k1 + 3) & 3];
        if (K.RemoveDoublet(v) != OpResult::Ok) { K.Rollback(); return 1; }
        ++doublets;
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
        ++corners;
        for (int x : {surv, o}) { dq.push_back(x); affected.push_back(x); }
      }
    }
    // edge swaps in the 1-ring of the collapsed element
    if (p_.edgeSwaps && K.VertAlive(s)) {
      for (int pass = 0; pass < 4; ++pass) {
        bool any = false;
        std::vector<int> faces = K.VF(s);
        for (int g : faces) {
          for (int j = 0; j < 4; ++j) {
            if (!K.FaceAlive(g)) break;
            int best = 0, bestVar = -1;
            for (int var = 0; var < 2; ++var) {
              int dlt;
              if (K.SwapEnergyDelta(g, j, var, &dlt) && dlt < best) { best = dlt; bestVar = var; }
            }
            if (bestVar < 0) continue;
            int h = K.AcrossEdge(g, j);
            Quad before_g = K.F[g], before_h = K.F[h];
            if (K.SwapEdge(g, j, bestVar) == OpResult::Ok) {
              ++swaps;
              any = true;
              for (int x : before_g) affected.push_back(x);
              for (int x : before_h) affected.push_back(x);
            }
          }
        }
        if (!any) break;
      }
    }
    std::vector<int> W;
    CollectRing(affected, W);
    workUnits_ += long(W.size());  // the step's size (with the checked elements below)
    LocalFit(W);
    memo_.Reset();  // positions and connectivity are frozen from here to Commit/Rollback
    for (auto& m : threadMemos_) m.Reset();
    // flip test on everything whose limit changed: vertices of ring1(W) (their limit normal
    // depends on their 1-ring) and the faces incident to them (centre limit depends on the
    // corners' 1-rings); refused if an element that agreed with the input does not now (all
    // elements are evaluated, the first failure in this order gives the refusal code)
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
    // Sequential part: which corners' vertex points to compute (shared caches).
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
    // The checks only read shared state (each element writes its own result slots and its own
    // side hint — a hint picks which ray answers a later query, so at most the rounding of that
    // answer, and one element writes it —; each thread has its own memo), so they run in
    // parallel (checkThreads_). Every check runs; the first failure in the sequential order
    // decides the refusal code, exactly as the sequential loop would.
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
    for (size_t i = 0; i < R1_.size(); ++i)
      if (vok_[R1_[i]] && !newVok_[i]) return Refuse(2);
    for (size_t i = 0; i < region_.size(); ++i) {
      if (info_[region_[i]].ok && !newInfo_[i].ok) return Refuse(2);
      if (!devOk_[i]) return Refuse(3);
    }
    CountStaleMemos();
    K.Commit();
    for (int v : R1_) vpcOk_[v] = 0;  // their committed vertex points changed
    for (int g : region_)
      for (int j = 0; j < 4; ++j) limOk_[K.F[g][j]] = 0;  // all of ring1(W)
    for (size_t i = 0; i < region_.size(); ++i) info_[region_[i]] = newInfo_[i];
    for (size_t i = 0; i < R1_.size(); ++i) { vok_[R1_[i]] = newVok_[i]; vhit_[R1_[i]] = newVhit_[i]; }
    // re-queue faces whose cost may have changed
    for (int g : region_) Push(g);
    res_.collapses++;
    res_.doublets += doublets;
    res_.swaps += swaps;
    res_.boundaryCorners += corners;
    return 0;
  }

  bool Run(Progress& prog) {
#ifdef _OPENMP
    // at most 2: a step checks a few dozen to a few hundred elements, and 2 is what was measured
    checkThreads_ = std::clamp(omp_get_max_threads(), 1, 2);
#endif
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
      if (p_.validateEveryOperation && r == 0) {
        std::string err = K.Check(&inv);
        if (err.empty() && vpcStale_ > 0) err = std::to_string(vpcStale_) + " stale cached vertex points";
        if (err.empty() && memoStale_ > 0) err = std::to_string(memoStale_) + " stale memoized centroids/neighbours";
        if (!err.empty()) {
          res_.error = "internal error: invalid mesh after collapse " + std::to_string(res_.collapses) + ": " + err;
          return false;
        }
      }
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
  std::vector<std::pair<int, int>> bseg_;
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

namespace {

// Adds a note to a result's message ("; "-separated).
void AppendMessage(std::string& message, const std::string& note) {
  message += (message.empty() ? "" : "; ") + note;
}

// What SimplifyToQuads refuses before any work (empty string: nothing).
std::string CheckInputs(const TriData& input, const TriData& start, const EmbreeScene& scene, const std::vector<double>& S,
                        const std::vector<double>& M, bool startAndQuads) {
  if (startAndQuads) return "initial quads and a start mesh cannot both be given";
  if (start.V.empty() || start.F.empty()) return "the start mesh is empty";
  const int nv = int(input.V.size());
  if (input.V.empty() || input.F.empty()) return "the input mesh is empty";
  if (int(S.size()) != nv || int(M.size()) != nv)
    return "fitmap size mismatch: " + std::to_string(S.size()) + " S and " + std::to_string(M.size()) +
           " M values for " + std::to_string(nv) + " vertices (compute the Fitmaps first)";
  int badS = 0;
  for (int i = 0; i < nv; ++i)
    if (!std::isfinite(S[i]) || !std::isfinite(M[i]) || S[i] < 0 || M[i] < 0) ++badS;
  if (badS) return std::to_string(badS) + " vertices have invalid (negative or non-finite) Fitmap values";
  if (!scene.Ok()) return "ray-casting scene: " + scene.Error();
  if (&scene.Mesh() != &input && scene.Mesh().F.size() != input.F.size())
    return "the Embree scene was not built on the input mesh";
  int nme = 0, nmv = 0;
  CountNonManifold(start, &nme, &nmv);
  if (nme || nmv)
    return "the input is not manifold: " + std::to_string(nme) + " non-manifold edges and " + std::to_string(nmv) +
           " non-manifold vertices (Filters > Cleaning and Repairing > Repair non Manifold Edges/Vertices)";
  return {};
}

// One simplification (§3.2-3.4) of checked inputs: tri-to-quad (or the given quads) of `start`,
// interpolation, collapses until the halting of `params`, final checks.
QuadSimplifyResult SimplifyOnce(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress prog, const std::vector<Quad>* initialQuads,
                                quad::LayoutGate* gate = nullptr, bool* cancelled = nullptr, double* gateWait = nullptr,
                                quad::LayoutGate* publishTo = nullptr) {
  QuadSimplifyResult res;
  const auto t0 = Clock::now();
  const int nv = int(input.V.size());
  prog(0, "Tri-to-quad", true);
  // 1. initial quads (§3.2)
  QuadData q0;
  if (initialQuads && !initialQuads->empty()) {
    q0.V = input.V;
    q0.F = *initialQuads;
    for (const Quad& q : q0.F)
      for (int x : q)
        if (x < 0 || x >= nv) { res.error = "initial quad references vertex " + std::to_string(x) + " out of range"; return res; }
    res.triToQuadPath = quad::TriToQuadPath::AlreadyQuads;
  } else {
    quad::TriToQuadResult tq = quad::TriToQuad(start, params.triToQuad);
    if (!tq.error.empty()) { res.error = "tri-to-quad: " + tq.error; return res; }
    q0 = std::move(tq.quads);
    res.triToQuadPath = tq.path;
  }
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
  if (res.collapses > 0) sim.FixFlips();
  res.flippedPatches = sim.CountFlipped();
  res.flippedVertices = sim.CountFlippedVertices();
  if (params.finalReinterpolation && res.collapses > 0) {
    // kept only if it does not add normal disagreements (it moves every control point)
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
  res.secondsSimplify = Since(t2);
  res.quads = sim.K.ToQuadData();
  res.patches = sim.K.NumFaces();
  res.valenceHistogram = sim.K.ValenceHistogram(&res.irregularVertices);
  res.secondsTotal = Since(t0);
  return res;
}

// Share (%) of `input`'s area in triangles none of whose sample points is reached: a point is
// unreached when its closest point on the tessellated limit `tess` (per-vertex `normal`s, scene
// `lim`) lies on a facet along the limit's boundary (`rimFacet`) and is not along the
// interpolated normal there (InterpolationCoverage). Per triangle, as the report's
// UnprojectablePercent (a triangle any normal line hits is reached): a jagged hole's rim
// triangles, partly beyond the smooth limit's outline, do not count. ~20k triangles tested (every
// k-th on large inputs); on small ones each triangle's L x L sub-triangle centroids are its
// samples (L <= 8), on large ones its centroid.
double UnreachedPercent(const TriData& input, const TriData& tess, const std::vector<Vec3>& normal,
                        const std::vector<char>& rimFacet, const EmbreeScene& lim) {
  const int nT = int(input.F.size()), stride = std::max(1, nT / 20000), m = (nT + stride - 1) / stride;
  const int L = std::clamp(int(std::sqrt(20000.0 / std::max(nT, 1))), 1, 8);
  const double tol = 0.0002 * BBoxDiagonal(input.V);
  std::vector<double> total(size_t(m), 0.0), missed(size_t(m), 0.0);  // summed in order below
#pragma omp parallel
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (int s = 0; s < m; ++s) {
      const auto& f = input.F[size_t(s) * stride];
      const Vec3 &a = input.V[f[0]], &b = input.V[f[1]], &c = input.V[f[2]];
      total[s] = 0.5 * (b - a).cross(c - a).norm();
      // sub-triangle centroids in barycentric steps of 1/L: (i + 1/3, j + 1/3) and (i + 2/3, j + 2/3);
      // the report's semantics: the triangle is reached if any part is, so the first reached
      // sample ends its test
      auto reachedAt = [&](double u, double v) {
        const Vec3 x = a + u * (b - a) + v * (c - a);
        const EmbreeScene::Hit h = lim.ClosestPoint(x, std::numeric_limits<double>::infinity(), hint);
        if (!h.valid) return false;
        hint = h.face;
        if (!rimFacet[h.face]) return true;  // inside the limit's outline: its normal line reaches x
        const auto& g = tess.F[h.face];
        Vec3 nrm = (1 - h.u - h.v) * normal[g[0]] + h.u * normal[g[1]] + h.v * normal[g[2]];
        if (nrm.norm() > 0) nrm.normalize();
        const Vec3 d = x - h.point;
        return (d - d.dot(nrm) * nrm).norm() <= std::max(tol, 0.2 * d.norm());
      };
      bool reached = false;
      for (int i = 0; i < L && !reached; ++i)
        for (int j = 0; i + j < L && !reached; ++j)
          for (int up = 0; up < (i + j + 1 < L ? 2 : 1) && !reached; ++up)
            reached = reachedAt((i + (up ? 2.0 : 1.0) / 3) / L, (j + (up ? 2.0 : 1.0) / 3) / L);
      if (!reached) missed[s] = total[s];
    }
  }
  double t = 0, mi = 0;
  for (int s = 0; s < m; ++s) { t += total[s]; mi += missed[s]; }
  return t > 0 ? 100.0 * mi / t : 0.0;
}

// How closely the interpolating limit of cage `q` follows the input, on a 6 x 6 tessellation per
// patch: `rms`, the RMS distance from (every k-th of at most ~100k) input vertices to it (to
// choose between two layouts); with `area`, `unreachedPct`, the share (%) of the input's area
// (~20k triangles, area-weighted) lying wholly beyond the limit's outline: their points' closest
// limit points are on the limit's boundary and not along the normal there, so no normal line
// from the limit reaches them (the paper's projectability, §3.4; an open cage's boundary curve
// cuts the input's rim, or a flat cage stops short of it). Lateral offsets up to 0.2 per
// mille of the diagonal or 20 % of the distance (the tessellation's facets: 11 degrees) count as
// along the normal; the absolute part is the narrowest band beyond the outline that is seen.
// Infinity / 100 % if the limit cannot be evaluated.
struct Coverage {
  double rms = std::numeric_limits<double>::infinity();
  double unreachedPct = 100.0;
};
Coverage InterpolationCoverage(const TriData& input, const QuadData& q, bool area) {
  Coverage cov;
  LimitSurface ls = LimitSurface::FromQuads(q);
  if (!ls.Ok() || ls.NumFaces() == 0) return cov;
  const int k = 6;
  TriData tess;
  std::vector<Vec3> normal;
  std::vector<char> rimFacet;  // area: per facet, whether it touches a boundary edge of the cage
  std::map<std::pair<int, int>, int> edgeUse;
  if (area)
    for (const Quad& f : q.F)
      for (int c = 0; c < 4; ++c) ++edgeUse[std::minmax(f[c], f[(c + 1) % 4])];
  tess.V.reserve(size_t(ls.NumFaces()) * (k + 1) * (k + 1));
  for (int f = 0; f < ls.NumFaces(); ++f) {
    const int base = int(tess.V.size());
    // corner c at (0,0), (1,0), (1,1), (0,1) (LimitSurface): edge c is v = 0, u = 1, v = 1, u = 0
    bool rim[4] = {false, false, false, false};
    if (area)
      for (int c = 0; c < 4; ++c) rim[c] = edgeUse[std::minmax(q.F[f][c], q.F[f][(c + 1) % 4])] == 1;
    for (int j = 0; j <= k; ++j)
      for (int i = 0; i <= k; ++i) {
        Vec3 P, Du, Dv;
        ls.Evaluate(f, double(i) / k, double(j) / k, q.V, &P, area ? &Du : nullptr, area ? &Dv : nullptr);
        tess.V.push_back(P);
        if (area) normal.push_back(Du.cross(Dv));
      }
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const int a = base + j * (k + 1) + i;
        tess.F.push_back({a, a + 1, a + k + 2});
        tess.F.push_back({a, a + k + 2, a + k + 1});
        if (area) {
          const char r = (rim[0] && j == 0) || (rim[1] && i == k - 1) || (rim[2] && j == k - 1) || (rim[3] && i == 0);
          rimFacet.push_back(r);
          rimFacet.push_back(r);
        }
      }
  }
  EmbreeScene lim(tess);
  if (!lim.Ok()) return cov;
  const int n = int(input.V.size()), stride = std::max(1, n / 100000), m = (n + stride - 1) / stride;
  std::vector<double> dSq(size_t(m), -1.0);  // summed in order below: the same sum on any thread count
#pragma omp parallel for schedule(static)
  for (int s = 0; s < m; ++s) {
    const Vec3& x = input.V[size_t(s) * stride];
    const EmbreeScene::Hit h = lim.ClosestPoint(x);
    if (h.valid) dSq[s] = (h.point - x).squaredNorm();
  }
  double sum = 0;
  long cnt = 0;
  for (double d : dSq)
    if (d >= 0) { sum += d; ++cnt; }
  cov.rms = cnt ? std::sqrt(sum / double(cnt)) : std::numeric_limits<double>::infinity();
  if (area) cov.unreachedPct = UnreachedPercent(input, tess, normal, rimFacet, lim);
  return cov;
}

double InterpolationRms(const TriData& input, const QuadData& q) { return InterpolationCoverage(input, q, false).rms; }

// RMS distance of the input's vertices to the limit of cage q after the final fit's least squares
// (FitCatmullClark, default parameters: what the pipeline's next filter does), absolute; infinite
// when the fit fails.
double FittedRms(const TriData& input, const EmbreeScene& scene, const QuadData& q) {
  const FitResult f = FitCatmullClark(q, input, scene);
  if (!f.error.empty() || f.dataRmsPerIteration.empty()) return std::numeric_limits<double>::infinity();
  return *std::min_element(f.dataRmsPerIteration.begin(), f.dataRmsPerIteration.end());
}

// Whether a retry g of the budget ladder covers the input about as well as the first pass r, which
// stopped above the budget: no more flipped patches and vertices, at most 0.1 % more of the input's
// area beyond its interpolating limit's outline (issue 13's unprojectable target), and, fitted as
// the next filter will fit it, an RMS distance to the input at most twice the first pass's scaled
// by the patch ratio (the error goes about as 1 / patches: bunny00 0.84 per mille at 400 patches,
// 0.35 at 1 000). Fitted, because the interpolating limit tells a cage that lost a part from one
// the fit can pull into place: on cow.off at 400 patches the first pass stopped at 421 (2.19 per
// mille after the fit); the relaxed pass's 392 patches had lost the legs (22 per mille after the
// fit, 3.7 % unprojectable), the 4 N start's 400 patches kept them (1.71) — and both interpolating
// limits were 21-22 per mille from the cow, with the same tail (99th percentile 98 / 123).
// `rFitted`: r's fitted RMS, computed on first use. `why`: the reason when not.
bool RetryCoversAsWell(const TriData& input, const EmbreeScene& scene, const QuadSimplifyResult& r,
                       const QuadSimplifyResult& g, double* rFitted, std::string* why) {
  char buf[240];
  if (g.flippedPatches + g.flippedVertices > r.flippedPatches + r.flippedVertices) {
    std::snprintf(buf, sizeof buf, "%d flipped patches and vertices (the first pass: %d)",
                  g.flippedPatches + g.flippedVertices, r.flippedPatches + r.flippedVertices);
    *why = buf;
    return false;
  }
  const Coverage cr = InterpolationCoverage(input, r.quads, true), cg = InterpolationCoverage(input, g.quads, true);
  const double diag = BBoxDiagonal(input.V);
  if (cg.unreachedPct > cr.unreachedPct + 0.1) {
    std::snprintf(buf, sizeof buf, "its interpolating limit leaves %.2f %% of the input's area unreached (the first pass: %.2f %%)",
                  cg.unreachedPct, cr.unreachedPct);
    *why = buf;
    return false;
  }
  if (*rFitted < 0) *rFitted = FittedRms(input, scene, r.quads);
  const double fitted = FittedRms(input, scene, g.quads);
  const double allowed = 2 * *rFitted * double(r.patches) / double(std::max(1, g.patches));
  if (fitted <= allowed) return true;
  std::snprintf(buf, sizeof buf, "fitted, its limit is %.3g per mille from the input (RMS; the first pass: %.3g, at most %.3g allowed)",
                1000 * fitted / diag, 1000 * *rFitted / diag, 1000 * allowed / diag);
  *why = buf;
  return false;
}

// The layout pass: S-cost order without the M test, down to `patches`.
QuadSimplifyParams LayoutParams(const QuadSimplifyParams& params, int patches) {
  QuadSimplifyParams lp = params;
  lp.layout = QuadSimplifyParams::Layout::PaperHalting;
  lp.useMFitmap = false;
  lp.targetPatches = patches;
  return lp;
}

// A budget of N patches (QuadSimplifyParams::targetPatches, Equalized): the layout pass alone,
// then a ladder of retries while the thin-part guard (and the flip check) stop it above N + 2 %
// (docs/quad.md "Budget ladder"). Each retry is kept only when it comes closer to N (a collapse on
// a thin tube can cascade through the doublets it leaves and land far below it) and covers the
// input about as well as the first pass (RetryCoversAsWell):
//  1. the guard's tolerance doubled (fandisk at 200 patches: 251 -> 200). Once only: at 4x the
//     tolerance elephant reached 200 patches with 10 % of its area unprojectable;
//  2. a start decimated to 4 N triangles (2 N quads), the guard as given, then doubled: on the
//     working start the guard keeps every finger of man's fist apart (1 788 patches for 400).
QuadSimplifyResult BudgetLadder(const TriData& input, const TriData& start, const EmbreeScene& scene,
                                const std::vector<double>& S, const std::vector<double>& M,
                                const QuadSimplifyParams& params, Progress& prog, const std::vector<Quad>* initialQuads) {
  const int target = params.targetPatches;
  const auto reached = [target](const QuadSimplifyResult& x) { return x.patches <= target + target / 50; };
  QuadSimplifyResult r = SimplifyOnce(input, start, scene, S, M, LayoutParams(params, target), prog, initialQuads);
  if (!r.error.empty() || reached(r) || !(params.deviationFactor > 0)) return r;
  QuadSimplifyResult best;  // the retry kept so far (patches 0: none)
  double spent = 0;         // seconds of the retries not kept
  std::string notes;        // why retries were not kept
  double rFitted = -1;      // the first pass's fitted RMS (RetryCoversAsWell)
  // one retry from `from` with the guard factor `guard`; rung: its place in the ladder
  auto attempt = [&](const TriData& from, double guard, int rung, const char* what) {
    QuadSimplifyParams lp = LayoutParams(params, target);
    lp.deviationFactor = guard;
    QuadSimplifyResult g = SimplifyOnce(input, from, scene, S, M, lp, prog.Sub(90, 100), initialQuads);
    const QuadSimplifyResult& cur = best.patches > 0 ? best : r;
    std::string why;
    if (!g.error.empty() || !(std::abs(g.patches - target) < std::abs(cur.patches - target)) ||
        !RetryCoversAsWell(input, scene, r, g, &rFitted, &why)) {
      spent += g.secondsTotal;
      if (!why.empty())
        AppendMessage(notes, std::string("a pass ") + what + " reached " + std::to_string(g.patches) +
                                 " patches but was not kept: " + why);
      return;
    }
    if (best.patches > 0) spent += best.secondsTotal;
    g.budgetRelaxations = rung;
    g.budgetDeviationFactor = guard;
    g.budgetFromPatches = r.patches;
    g.budgetStartFaces = &from == &start ? 0 : int(from.F.size());
    best = std::move(g);
  };
  attempt(start, 2 * params.deviationFactor, 1, "with the thin-part guard's tolerance doubled");
  const long coarseFaces = 4L * target;
  if (!(best.patches > 0 && reached(best)) && !(initialQuads && !initialQuads->empty()) &&
      long(start.F.size()) > coarseFaces + coarseFaces / 4) {
    WorkingResolutionParams wp;
    wp.maxFaces = int(coarseFaces);
    const DecimateResult coarse = WorkingResolution(start, wp);
    // a decimation that stopped far above 4 N (no valid collapse left: b9_mesh stopped at 1 958
    // triangles for 800, whose pairing failed and whose 5 874 split quads took 78 s per pass and
    // ended at 5 165 patches) is no coarser start: skipped
    if (coarse.decimated && long(coarse.mesh.F.size()) <= coarseFaces + coarseFaces / 2) {
      spent += coarse.seconds;
      attempt(coarse.mesh, params.deviationFactor, 2, "from a start of 4 x the budget in triangles");
      if (!(best.patches > 0 && reached(best)))
        attempt(coarse.mesh, 2 * params.deviationFactor, 3,
                "from a start of 4 x the budget in triangles, the guard's tolerance doubled");
    }
  }
  QuadSimplifyResult& kept = best.patches > 0 ? best : r;
  if (!notes.empty()) AppendMessage(kept.message, notes);
  if (best.patches == 0) {
    r.secondsTotal += spent;
    r.secondsBudgetRetries = spent;
    return r;
  }
  best.secondsBudgetRetries = r.secondsTotal + spent;
  best.secondsTotal += best.secondsBudgetRetries;
  return best;
}

}  // namespace

namespace {
QuadSimplifyResult SimplifyFromStart(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
                                     const std::vector<double>& M, const QuadSimplifyParams& params,
                                     vcg::CallBackPos* cb, const std::vector<Quad>* initialQuads,
                                     const TriData* startMesh) {
  // the valence term is the layout pass's: the paper's halting (its own mode and the count pass)
  // keeps the paper's cost (docs/quad.md "Regularity")
  if (params.layout == QuadSimplifyParams::Layout::PaperHalting && params.valenceWeight != 0) {
    QuadSimplifyParams paper = params;
    paper.valenceWeight = 0;
    return SimplifyToQuads(input, scene, S, M, paper, cb, initialQuads, startMesh);
  }
  const TriData& start = startMesh ? *startMesh : input;
  QuadSimplifyResult res;
  res.error = CheckInputs(input, start, scene, S, M, startMesh && initialQuads && !initialQuads->empty());
  if (!res.error.empty()) return res;
  Progress prog(cb);
  auto layoutParams = [&params](int patches) { return LayoutParams(params, patches); };
  // Coverage guard (QuadSimplifyParams::coverageRmsPermille, coverageUnprojectablePct): a cage
  // whose interpolating limit leaves the input, or leaves part of it unreached by projection, is
  // laid out again with twice the patches.
  auto guard = [&](QuadSimplifyResult r) {
    const double diag = BBoxDiagonal(input.V);
    const bool byRms = params.coverageRmsPermille > 0, byArea = params.coverageUnprojectablePct > 0;
    if (!(byRms || byArea) || !(diag > 0)) return r;
    // how far a cage is from covering: > 1 when a trigger fires (the larger of the two ratios)
    auto excess = [&](double rms, double unproj) {
      return std::max(byRms ? rms / (params.coverageRmsPermille / 1000.0 * diag) : 0.0,
                      byArea ? unproj / params.coverageUnprojectablePct : 0.0);
    };
    const Coverage c0 = byArea || !(r.layoutRms > 0) ? InterpolationCoverage(input, r.quads, byArea) : Coverage{};
    double rms = byRms ? (r.layoutRms > 0 ? r.layoutRms : c0.rms) : 0.0;
    double unproj = byArea ? c0.unreachedPct : 0.0;
    r.layoutUnprojectablePct = byArea ? unproj : -1;
    const int maxPatches = std::max(1, int(start.F.size()) / 4);  // half the start's quads
    // The target doubles each time; a pass can land below it (on a thin tube one collapse can
    // cascade through the doublets it leaves, cyl_capped: target 48 -> 6 patches), so a pass is
    // kept only when it comes closer to covering the input.
    int target = r.patches;
    const int from = r.patches;
    const double fromRms = rms, fromUnproj = unproj;
    for (int k = 0; k < 8 && excess(rms, unproj) > 1 && 2 * target <= maxPatches; ++k) {
      target *= 2;
      QuadSimplifyResult g =
          SimplifyOnce(input, start, scene, S, M, layoutParams(target), prog.Sub(90, 100), initialQuads);
      if (!g.error.empty()) break;
      const Coverage gc = InterpolationCoverage(input, g.quads, byArea);
      g.layoutRms = gc.rms;
      const double gUnproj = byArea ? gc.unreachedPct : 0.0;
      r.secondsTotal += g.secondsTotal;
      if (!(excess(byRms ? g.layoutRms : 0.0, gUnproj) < excess(rms, unproj))) continue;
      g.coverageRelayouts = k + 1;
      g.coverageFromPatches = from;
      g.coverageFromRms = fromRms;
      g.coverageFromUnprojectablePct = fromUnproj;
      g.layoutUnprojectablePct = byArea ? gUnproj : -1;
      g.countPatches = r.countPatches;
      g.countStartFaces = r.countStartFaces;
      g.rejectedByM = r.rejectedByM;
      g.secondsCount = r.secondsCount;
      g.paperLayoutRms = r.paperLayoutRms;
      g.equalizedLayoutRms = r.equalizedLayoutRms;
      g.secondsTotal = r.secondsTotal;
      rms = byRms ? g.layoutRms : 0.0;
      unproj = gUnproj;
      r = std::move(g);
    }
    r.coverageOutOfRoom = excess(rms, unproj) > 1 && 2 * target > maxPatches;
    return r;
  };
  const bool equalized = params.layout == QuadSimplifyParams::Layout::Equalized;
  if (equalized && params.targetPatches > 0)  // a budget: the layout pass alone (M would halt above it)
    return BudgetLadder(input, start, scene, S, M, params, prog, initialQuads);
  if (!equalized || !params.useMFitmap) return SimplifyOnce(input, start, scene, S, M, params, prog, initialQuads);

  // Count pass (docs/quad.md "Layout"): the paper's halting on a coarse start mesh; given quads
  // are counted as they are.
  const auto t0 = Clock::now();
  DecimateResult coarse;
  const bool decimate = !(initialQuads && !initialQuads->empty()) && params.countFaces > 0 &&
                        int(start.F.size()) > params.countFaces + params.countFaces / 4;
  auto decimateCountStart = [&] {
    WorkingResolutionParams wp;
    wp.maxFaces = params.countFaces;
    coarse = WorkingResolution(start, wp);
  };
  QuadSimplifyParams cp = params;
  cp.layout = QuadSimplifyParams::Layout::PaperHalting;
  cp.valenceWeight = 0;  // the paper's count
  QuadSimplifyResult c;
  bool counted = false;        // c holds the count pass (or its error)
  bool recounted = false;      // c holds the count pass on `start` after one on `coarse` (the worker's recount)
  double countOverlap = 0;     // seconds of the count pass hidden behind the layout pass
  // The two passes overlap (docs/quad.md "Layout"): the layout pass needs the count only at its
  // end, so with two threads the count pass (decimation included) runs on a second thread with
  // serial checks while the layout pass runs here (quad::LayoutGate). On a coarse count start the
  // layout pass goes on down to the largest count that needs no recount (countFaces / 16) and
  // waits there for the count; a count that needs a recount raises that floor to
  // recountFloorFactor x itself (or to where the layout pass is, if lower) and recounts on the
  // second thread too. A count on the layout pass's own start (a small start, or the recount)
  // lets the layout pass go on while it stays above that pass's live count. A count below a step
  // the layout pass has taken, or an error, cancels it, and the rest runs in sequence. The cages
  // are the same as in sequence (no step depends on the threads).
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  if (threads >= 2 && params.parallelChecks != QuadSimplifyParams::ParallelChecks::Never) {
    // (no floor on the count's own start: only its live count lets the layout pass go on)
    quad::LayoutGate gate(decimate ? std::max(1, params.countFaces / 16) : std::numeric_limits<int>::max());
    double countWall = 0;
    std::thread worker([&] {
      const auto w0 = Clock::now();
      int target = -1;
      try {
        QuadSimplifyParams wcp = cp;
        wcp.parallelChecks = QuadSimplifyParams::ParallelChecks::Never;
        if (!decimate) {
          c = SimplifyOnce(input, start, scene, S, M, wcp, Progress(nullptr), initialQuads, nullptr, nullptr, nullptr,
                           &gate);
          counted = true;
          if (c.error.empty()) target = std::max(1, c.patches);
        } else {
          decimateCountStart();
          if (coarse.decimated) {
            c = SimplifyOnce(input, coarse.mesh, scene, S, M, wcp, Progress(nullptr), initialQuads);
            counted = true;
            // A count the coarse start bounds is counted again on the real start, here, while the
            // layout pass goes on down to a bound of the recount (recountFloorFactor x the coarse
            // count) or, when it is already below that, waits where it is, and then follows the
            // recount's live count.
            if (c.error.empty() && 16L * c.patches > long(coarse.mesh.F.size())) {
              gate.RaiseFloor(params.recountFloorFactor * c.patches);
              c = SimplifyOnce(input, start, scene, S, M, wcp, Progress(nullptr), initialQuads, nullptr, nullptr,
                               nullptr, &gate);
              recounted = true;
            }
            if (c.error.empty()) target = std::max(1, c.patches);
          }
        }
      } catch (const std::exception& e) {
        c = QuadSimplifyResult();
        c.error = std::string("count pass: ") + e.what();
        counted = true;
      }
      countWall = Since(w0);
      gate.Set(target);
    });
    bool cancelled = false;
    double gateWait = 0;
    try {
      res = SimplifyOnce(input, start, scene, S, M, layoutParams(0), prog.Sub(0, 100), initialQuads, &gate, &cancelled,
                         &gateWait);
    } catch (...) {
      worker.join();  // it never waits for this thread
      throw;
    }
    const auto j0 = Clock::now();
    worker.join();
    const double joinWait = Since(j0);
    if (counted && !c.error.empty()) return c;
    if (!res.error.empty()) return res;
    if (!cancelled && gate.Target() > 0) {
      res.secondsSimplify -= gateWait;  // the wait inside the layout pass is the count's
      res.secondsTotal -= gateWait;
      countOverlap = std::max(0.0, countWall - gateWait - joinWait);
    } else {
      // laid out again below, after the recount; also when the layout pass ended (no collapse
      // left) before the cancellation reached it: the recount may stop above where it ended
      res = QuadSimplifyResult();
    }
  } else if (decimate) {
    decimateCountStart();
  }
  const TriData& countStart = decimate && coarse.decimated ? coarse.mesh : start;
  if (!counted) {
    c = SimplifyOnce(input, countStart, scene, S, M, cp, prog.Sub(0, 30), initialQuads);
    if (!c.error.empty()) return c;
  }
  // A count above 1/16 of the coarse start's triangles (its quads reduced less than 8x) is bounded
  // by that start's resolution: count again on the real start mesh.
  const bool recount = recounted || (&countStart != &start && 16L * c.patches > long(countStart.F.size()));
  if (recount && !recounted) {
    c = SimplifyOnce(input, start, scene, S, M, cp, prog.Sub(0, 30), initialQuads);
    if (!c.error.empty()) return c;
  }
  if (res.patches == 0)  // not laid out beside the count
    res = SimplifyOnce(input, start, scene, S, M, layoutParams(std::max(1, c.patches)), prog.Sub(30, 100), initialQuads);
  if (!res.error.empty()) return res;
  // When the count pass ran on the real start mesh it is the paper's own result: keep whichever
  // of the two cages' interpolating limits follows the input more closely (docs/quad.md "Layout").
  const bool paperResult = recount || &countStart == &start;
  if (paperResult) {
    res.layoutRms = InterpolationRms(input, res.quads);
    c.layoutRms = InterpolationRms(input, c.quads);
    res.paperLayoutRms = c.layoutRms;
    if (c.layoutRms < res.layoutRms) {
      const double eqRms = res.layoutRms;
      res = std::move(c);
      res.paperLayoutRms = res.layoutRms;
      res.equalizedLayoutRms = eqRms;
      res.keptPaperLayout = true;
      res.countPatches = res.patches;
      res.countStartFaces = int(start.F.size());
      // (the stages then sum to the wall time: "count pass" is what the other passes added,
      // beside this one or after it)
      const double own = res.secondsTotal;
      res.secondsTotal = std::chrono::duration<double>(Clock::now() - t0).count();
      res.secondsCount = std::max(0.0, res.secondsTotal - own);
      return guard(std::move(res));
    }
    res.equalizedLayoutRms = res.layoutRms;
  }
  res.countPatches = c.patches;
  res.countStartFaces = int((recount ? start : countStart).F.size());
  res.rejectedByM = c.rejectedByM;
  res.secondsCount = std::chrono::duration<double>(Clock::now() - t0).count() - res.secondsTotal;
  res.secondsCountOverlapped = countOverlap;
  res.secondsTotal += res.secondsCount;
  return guard(std::move(res));
}

}  // namespace

// A start mesh too coarse for the input (docs/quad.md "A start too coarse"): the simplification
// only removes patches, so the start bounds the cage. A cage that keeps more than half of its
// start's quads (the start's resolution, not the Fitmaps, decided it) and whose interpolating
// limit stays farther than startRmsPermille from the input is simplified again from its start
// refined at edge midpoints (the same surface, x4 triangles; up to twice, while under
// kMaxRefinedStartFaces), and the finer start's cage kept when, fitted, it is closer to the input.
// rotor.off (1 200 long CAD triangles, 599 pairs) stopped at 515 patches whose interpolating limit
// was 45 per mille from the part (40 after the fit, 21 displaced). The same when the coverage
// guard ran out of room (it could not double the patches) with the limit that far off
// (oblong-shuffled: 230 patches, 76 per mille); not for the guard's unreached area alone (b9_mesh,
// limit 2.6 per mille from the input, went from 1 836 to 7 696 patches).
QuadSimplifyResult SimplifyToQuads(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
                                   const std::vector<double>& M, const QuadSimplifyParams& params,
                                   vcg::CallBackPos* cb, const std::vector<Quad>* initialQuads,
                                   const TriData* startMesh) {
  QuadSimplifyResult r = SimplifyFromStart(input, scene, S, M, params, cb, initialQuads, startMesh);
  // (the paper's literal mode and a budget keep their start; given quads are simplified as they are)
  if (!r.error.empty() || (initialQuads && !initialQuads->empty()) || params.targetPatches > 0 ||
      params.layout != QuadSimplifyParams::Layout::Equalized)
    return r;
  constexpr long kMaxRefinedStartFaces = 65536;
  DecimateResult finer;
  const TriData* start = startMesh ? startMesh : &input;
  const double diag = BBoxDiagonal(input.V);
  double rFitted = -1;  // r's fitted RMS (computed on first use)
  auto layoutRms = [&](QuadSimplifyResult& x) {
    if (!(x.layoutRms > 0)) x.layoutRms = InterpolationRms(input, x.quads);
    return x.layoutRms;
  };
  auto needsFiner = [&](QuadSimplifyResult& x, const TriData& st) {
    return params.startRmsPermille > 0 && (4L * x.patches > long(st.F.size()) || x.coverageOutOfRoom) &&
           layoutRms(x) > params.startRmsPermille / 1000.0 * diag;
  };
  for (int k = 0; k < 2 && 4L * long(start->F.size()) <= kMaxRefinedStartFaces && needsFiner(r, *start); ++k) {
    WorkingResolutionParams wp;
    wp.minFaces = int(4 * start->F.size());
    DecimateResult next = WorkingResolution(*start, wp);
    if (next.refinements == 0) break;
    QuadSimplifyResult g = SimplifyFromStart(input, scene, S, M, params, cb, nullptr, &next.mesh);
    // judged fitted, as the next filter will fit it (the interpolating limit is a poor predictor:
    // RetryCoversAsWell)
    if (rFitted < 0) rFitted = FittedRms(input, scene, r.quads);
    const double gFitted = g.error.empty() ? FittedRms(input, scene, g.quads) : rFitted;
    if (!g.error.empty() || !(gFitted < rFitted)) {
      r.secondsTotal += g.secondsTotal;
      r.secondsStartRetries += g.secondsTotal;
      AppendMessage(r.message, "a start refined at edge midpoints (" + std::to_string(next.mesh.F.size()) +
                                   " triangles) did not cover the input better (" + std::to_string(g.patches) +
                                   " patches): kept the cage of the coarser start");
      break;
    }
    rFitted = gFitted;
    g.secondsStartRetries = r.secondsTotal;
    g.startRefinements = r.startRefinements + next.refinements;
    g.startRefinedFrom = r.startRefinedFrom > 0 ? r.startRefinedFrom : r.patches;
    g.secondsTotal += r.secondsTotal;
    r = std::move(g);
    finer = std::move(next);
    start = &finer.mesh;
  }
  return r;
}

}  // namespace vcgext
