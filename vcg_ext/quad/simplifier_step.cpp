/// \file simplifier_step.cpp
/// One step of the Simplifier (Fitmaps §3.3–3.4): a diagonal collapse, the doublets and flat
/// boundary corners it leaves, edge swaps round its survivor, the local fit of the moved ring, and
/// the checks that keep or undo it (flips, the geometric guard).
#include <vector>

#include "vcg_ext/quad/simplifier.h"

namespace vcgext {
namespace simplify_internal {

void Simplifier::LocalFit(const std::vector<int>& W, int rounds) {
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

void Simplifier::CountStaleMemos() {
  if (!p_.validateEveryOperation) return;
  memoStale_ += memo_.CountStale();
  for (const auto& m : threadMemos_) memoStale_ += m.CountStale();
}

int Simplifier::Refuse(int code) {
  CountStaleMemos();
  K.Rollback();
  return code;
}

bool Simplifier::RemoveDoubletsAndCorners(std::vector<int> dq, std::vector<int>& affected, StepCounts& n) {
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

void Simplifier::SwapAround(int s, std::vector<int>& affected, StepCounts& n) {
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

void Simplifier::CollectCheckRegion(const std::vector<int>& W) {
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

void Simplifier::RunChecks() {
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

int Simplifier::Verdict() const {
  for (size_t i = 0; i < R1_.size(); ++i)
    if (vok_[R1_[i]] && !newVok_[i]) return 2;
  for (size_t i = 0; i < region_.size(); ++i) {
    if (info_[region_[i]].ok && !newInfo_[i].ok) return 2;
    if (!devOk_[i]) return 3;
  }
  return 0;
}

void Simplifier::CommitCaches() {
  K.Commit();
  for (int v : R1_) vpcOk_[v] = 0;  // their committed vertex points changed
  for (int g : region_)
    for (int j = 0; j < 4; ++j) limOk_[K.F[g][j]] = 0;  // all of ring1(W)
  for (size_t i = 0; i < region_.size(); ++i) info_[region_[i]] = newInfo_[i];
  for (size_t i = 0; i < R1_.size(); ++i) { vok_[R1_[i]] = newVok_[i]; vhit_[R1_[i]] = newVhit_[i]; }
  // re-queue faces whose cost may have changed
  for (int g : region_) Push(g);
}

int Simplifier::FitCheckCommit(const std::vector<int>& W) {
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

int Simplifier::Step(int f, int k) {
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

}  // namespace simplify_internal
}  // namespace vcgext
