/// \file simplifier.cpp
/// One simplification pass (Fitmaps §3.2–3.4), SimplifyOnce: the initial quads and their
/// interpolating control points, the Simplifier's caches, its pass (steps in cost order until the
/// pass's halting) and the final checks. A step itself is in simplifier_step.cpp.
#include <algorithm>
#include <string>
#include <vector>

#include "vcg_ext/quad/simplifier.h"
#include "vcg_ext/quad/tri_to_quad.h"

namespace vcgext {
namespace simplify_internal {

Simplifier::Simplifier(const TriData& in, const TriData& start, const EmbreeScene& scene, const std::vector<double>& S,
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

quad::InterpolationStats Simplifier::Reinterpolate() {
  std::vector<Vec3> targets(K.NumVertexSlots(), Vec3::Zero());
  std::vector<int> alive;
  for (int v = 0; v < K.NumVertexSlots(); ++v)
    if (K.VertAlive(v)) alive.push_back(v);
#pragma omp parallel for schedule(dynamic, 64)
  for (long i = 0; i < long(alive.size()); ++i) targets[alive[i]] = VertexTarget(alive[i]);
  return quad::SolveInterpolationGlobal(K, targets, tol_);
}

void Simplifier::Initialize() {
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

bool Simplifier::Validate(const QuadMesh::Invariants& inv) {
  std::string err = K.Check(&inv);
  if (err.empty() && vpcStale_ > 0) err = std::to_string(vpcStale_) + " stale cached vertex points";
  if (err.empty() && memoStale_ > 0) err = std::to_string(memoStale_) + " stale memoized centroids/neighbours";
  if (err.empty()) return true;
  res_.error = "internal error: invalid mesh after collapse " + std::to_string(res_.collapses) + ": " + err;
  return false;
}

bool Simplifier::Run(Progress& prog) {
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

int Simplifier::FixFlips() {
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

int Simplifier::CountFlipped() const {
  int bad = 0;
  for (int f = 0; f < K.NumFaceSlots(); ++f)
    if (K.FaceAlive(f) && !EvalFace(f).ok) ++bad;
  return bad;
}

int Simplifier::CountFlippedVertices() const {
  int bad = 0;
  for (int v = 0; v < K.NumVertexSlots(); ++v)
    if (K.VertAlive(v) && !VertexOk(v)) ++bad;
  return bad;
}

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

}  // namespace simplify_internal
}  // namespace vcgext
