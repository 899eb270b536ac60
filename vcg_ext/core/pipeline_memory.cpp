#include "vcg_ext/core/pipeline_memory.h"

#include "vcg_ext/core/memory.h"

namespace vcgext {

namespace {

// Growth of the resident memory during each filter (its peak minus the resident memory when it
// started) in meshlabserver, meshlab_scripts/pipeline.mlx at its defaults, bunny00 and its
// midpoint refinements (bench/dense_bench.py's inputs), 2026-12-07 (MB):
//
//   triangles   Compute Fitmaps   Quad Simplification   Fit and Bake
//   75 408            36                 20                  76
//   301 632          182                 37                 243
//   1 206 528        740                130                 752
//   4 826 112       2811                793                2650
//
// and Compute Fitmaps at every vertex (workingFaces 0; bench_fitmaps, whose peak includes its
// input): 197 MB at 302k, 811 MB at 1.2 M. Each estimate is a line above every measurement: a
// fixed part plus MB per million triangles (the working copy, its Embree scene, the working
// resolution's decimation of a copy, the per-vertex results; the fit's tessellations, atlas and
// second scene).
struct Line {
  double fixedMb, mbPerMillion;
};
constexpr Line kFitmaps{40, 680}, kSimplification{30, 170}, kFitAndBake{80, 570};

}  // namespace

double EstimatePipelineMemoryMb(PipelineStep step, double triangles) {
  const Line l = step == PipelineStep::Fitmaps ? kFitmaps
                 : step == PipelineStep::Simplification ? kSimplification : kFitAndBake;
  return l.fixedMb + l.mbPerMillion * triangles / 1e6;
}

std::string CheckPipelineMemory(PipelineStep step, double triangles, double budgetMb) {
  const std::string layer = step == PipelineStep::FitAndBake ? "reference layer" : "layer";
  const std::string err = CheckMemory(EstimatePipelineMemoryMb(step, triangles), budgetMb,
                                      "a " + layer + " of " + std::to_string(long(triangles)) + " triangles");
  if (err.empty()) return err;
  return err + ": decimate the " + layer +
         " first (Filters > Remeshing, Simplification and Reconstruction > Simplification: Quadric Edge "
         "Collapse Decimation; a scan of a few million triangles gives the same cage), or free memory";
}

}  // namespace vcgext
