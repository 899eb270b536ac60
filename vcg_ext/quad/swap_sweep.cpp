/// \file swap_sweep.cpp
/// The swap sweep (beyond the paper; docs/quad.md "Swap sweep", issue 13): after the last
/// collapse, chains of edge swaps that cancel pairs of singularities, each checked as a step.
#include <vector>

#include "vcg_ext/quad/simplifier.h"

namespace vcgext {
namespace simplify_internal {

int Simplifier::SwapSweep(int passes) {
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

bool Simplifier::BestSwap(int g, int j, int* var, int* delta) const {
  *var = -1;
  for (int v = 0; v < 2; ++v) {
    int d;
    if (K.SwapEnergyDelta(g, j, v, &d) && (*var < 0 || d < *delta)) { *delta = d; *var = v; }
  }
  return *var >= 0;
}

std::vector<int> Simplifier::EdgeFaceCorners(int g, int j) const {
  const int h = K.AcrossEdge(g, j);
  std::vector<int> c(K.F[g].begin(), K.F[g].end());
  c.insert(c.end(), K.F[h].begin(), K.F[h].end());
  return c;
}

bool Simplifier::ChainFrom(int g, int j, int depth, std::vector<int>& seeds) {
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

bool Simplifier::LoweringChain(const std::vector<int>& around, int depth, std::vector<int>& seeds) {
  for (int x : around) {
    if (!K.VertAlive(x)) continue;
    const std::vector<int> faces = K.VF(x);
    for (int g : faces)
      for (int j = 0; j < 4 && K.FaceAlive(g); ++j)
        if (ChainFrom(g, j, depth, seeds)) return true;
  }
  return false;
}

bool Simplifier::SweepSwap(int g, int j) {
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
