// What both plugin classes (MeshLab 2020.09's MeshFilterInterface, filter_fitmap_quad.cpp, and
// 2022.02+'s FilterPlugin, api2025/) do by filter id: one switch each, here.
#include "filter_table.h"
#include "glue.h"
#include "vcg_ext/core/memory.h"

namespace fitmapquad {

int PostConditionOf(int id) {
  switch (id) {
    case FP_COMPUTE_FITMAPS:
      return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
    case FP_QUAD_SIMPLIFICATION:
    case FP_FIT_AND_BAKE:
    case FP_LOOP_REFINE:
      return MeshModel::MM_NONE;  // the input layers are not modified; new layers are added
    case FP_LOOP_SNAP:
      return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTQUALITY;
    case FP_LOOP_CURVATURE:
      return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
  }
  return MeshModel::MM_ALL;
}

void InitParamsOf(int id, const MeshDocument& md, RichParameterList& par) {
  switch (id) {
    case FP_COMPUTE_FITMAPS: InitFitmapsParams(md, par); break;
    case FP_QUAD_SIMPLIFICATION: InitQuadParams(md, par); break;
    case FP_FIT_AND_BAKE: InitFitParams(md, par); break;
    case FP_LOOP_REFINE: InitLoopRefineParams(md, par); break;
    case FP_LOOP_SNAP: InitLoopSnapParams(md, par); break;
    case FP_LOOP_CURVATURE: InitLoopCurvatureParams(md, par); break;
  }
}

bool ApplyOf(int id, GlueContext& ctx) {
  if (ctx.md.mm() == nullptr) return ctx.Fail("no current layer");
  vcgext::StagePeakMemoryMb();  // the filter's stages measure their own peak memory from here
  switch (id) {
    case FP_COMPUTE_FITMAPS: return ApplyFitmaps(ctx);
    case FP_QUAD_SIMPLIFICATION: return ApplyQuad(ctx);
    case FP_FIT_AND_BAKE: return ApplyFit(ctx);
    case FP_LOOP_REFINE: return ApplyLoopRefine(ctx);
    case FP_LOOP_SNAP: return ApplyLoopSnap(ctx);
    case FP_LOOP_CURVATURE: return ApplyLoopCurvature(ctx);
  }
  return ctx.Fail("unknown filter");
}

}  // namespace fitmapquad
