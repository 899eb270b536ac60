#pragma once
/// \file working_start.h
/// Where the quad simplification of a dense input starts (paper §4, "a mesh M' with about 100K
/// triangles"; issue 12; docs/multires.md "A coarser first start"): a first try from a coarser
/// decimation, and the working resolution M'_S only when that start limited the result.
#include <string>

#include "vcg_ext/core/decimate.h"
#include "vcg_ext/quad/quad_simplify.h"

namespace vcgext {

/// The cage and the start it was simplified from (SimplifyFromWorkingStart).
struct WorkingStartResult {
  QuadSimplifyResult result;  ///< the kept cage (result.error set on failure)
  StartMesh start;            ///< its start mesh (start.differs false: the input itself)
  /// The first, coarser start (0: not tried: the input is not denser than the working resolution,
  /// or the first start would not be coarser than it).
  int firstStartFaces = 0;
  int firstPatches = 0;         ///< the first start's cage (when tried)
  double firstSeconds = 0;      ///< its decimation and simplification
  bool firstKept = false;       ///< true: that cage is `result`
  std::string fallbackReason;   ///< why it was not kept (empty when kept or not tried)
};

/// A sliver: a triangle with an angle below this (degrees).
inline constexpr double kSliverAngleDeg = 10;
/// The first start is not used when it has more than this share (percentage points) of slivers
/// beyond the input's: decimated that far, a part with flat faces (CAD) turns its planes into
/// slivers whose quads the simplification cannot collapse (fandisk made 4x denser, decimated to
/// 10k triangles: 6.0 % slivers against the input's 0.0 %, its pass 12 s for a cage of 2 013 patches
/// instead of 763; the data set's scans above 40k triangles: 0.1-0.4 %).
inline constexpr double kMaxAddedSliverPct = 1.0;
/// Under a budget the first start runs its own budget ladder (its coarse starts are decimations of
/// the first start instead of the working resolution) and is kept when its cage is at most this
/// many times the budget; farther, the working resolution runs with its ladder. Measured
/// (docs/multires.md "The first start's own ladder", dense copies and the data set's scans above
/// 40k triangles @ 200 / 400): where a first pass stopped above the budget its ladder reached 400
/// on every copy (camel x4: 400 patches, 0.99 per mille, instead of the working resolution's 443,
/// 1.23) and came within 1.10 x of 200 where the working resolution's ended at 1.11-1.13 x (man,
/// triceratops, elephant copies); the one beyond (camel x4 @ 200: 426) falls back, as before.
inline constexpr double kFirstStartBudgetSlack = 1.1;
/// Share (%) of the triangles of `m` that are slivers (kSliverAngleDeg).
double SliverSharePct(const TriData& m);

/// SimplifyToQuads from the start ChooseStartMesh(input, sp) picks, except for a dense input (more
/// triangles than sp.workingFaces > firstFaces > 0): that is first simplified from its decimation to
/// max(firstFaces, 4 targetPatches) triangles, and from the working resolution only when that
/// first cage was limited by its start (without a budget: its count above 1/16 of the start's
/// triangles, CountBoundedByStart; under one: above kFirstStartBudgetSlack x the budget after its
/// own ladder) or would have needed one of the
/// retries SimplifyToQuads runs without a budget (coverage guard, start refinement, rescue: the
/// first pass runs without them), or when that start has too many slivers (kMaxAddedSliverPct: no
/// first pass). Measured (docs/multires.md "A coarser
/// first start"): bunny00 and the data set's other scans above 40k triangles keep their errors
/// (geometric means x0.98-1.01) at two thirds of the wall time; a CAD part decimated that far can
/// lose its simplifiability (fandisk_large, 31k triangles, from 10k: 1 025 patches instead of 268
/// at tau = 1 %, 847 for a budget of 400), which the rule catches by the count or the budget.
/// `initialQuads` (a pure-quad layer): simplified from them, no start mesh.
WorkingStartResult SimplifyFromWorkingStart(const TriData& input, const EmbreeScene& scene,
                                            const std::vector<double>& S, const std::vector<double>& M,
                                            const QuadSimplifyParams& params, const StartMeshParams& sp,
                                            int firstFaces, vcg::CallBackPos* cb = nullptr,
                                            const std::vector<Quad>* initialQuads = nullptr);

}  // namespace vcgext
