#include "filter_fitmap_quad.h"

#include <exception>

#include "filter_table.h"
#include "glue.h"
#include "vcg_ext/core/memory.h"

using namespace fitmapquad;


FilterFitmapQuadPlugin::FilterFitmapQuadPlugin() {
  for (const auto& f : AllFilters()) {
    typeList << f.id;
    actionList << new QAction(QString(f.name), this);
  }
}

FilterFitmapQuadPlugin::~FilterFitmapQuadPlugin() = default;

QString FilterFitmapQuadPlugin::filterName(FilterIDType id) const {
  const FilterSpec* s = Spec(id);
  return s ? QString(s->name) : QString("unknown filter");
}

QString FilterFitmapQuadPlugin::filterInfo(FilterIDType id) const {
  const FilterSpec* s = Spec(id);
  return s ? QString(s->info) : QString();
}

MeshFilterInterface::FilterClass FilterFitmapQuadPlugin::getClass(QAction* a) {
  const FilterSpec* s = Spec(ID(a));
  return s ? FilterClass(s->classes) : MeshFilterInterface::Remeshing;
}

MeshFilterInterface::FILTER_ARITY FilterFitmapQuadPlugin::filterArity(QAction*) const {
  return SINGLE_MESH;
}

int FilterFitmapQuadPlugin::getPreConditions(QAction*) const { return MeshModel::MM_NONE; }

int FilterFitmapQuadPlugin::postCondition(QAction* a) const {
  switch (ID(a)) {
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

void FilterFitmapQuadPlugin::initParameterSet(QAction* a, MeshDocument& md, RichParameterList& par) {
  switch (ID(a)) {
    case FP_COMPUTE_FITMAPS: InitFitmapsParams(md, par); break;
    case FP_QUAD_SIMPLIFICATION: InitQuadParams(md, par); break;
    case FP_FIT_AND_BAKE: InitFitParams(md, par); break;
    case FP_LOOP_REFINE: InitLoopRefineParams(md, par); break;
    case FP_LOOP_SNAP: InitLoopSnapParams(md, par); break;
    case FP_LOOP_CURVATURE: InitLoopCurvatureParams(md, par); break;
  }
}

bool FilterFitmapQuadPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                         vcg::CallBackPos* cb) {
  if (md.mm() == nullptr) {
    errorMessage = "no current layer";
    Log("Error: no current layer");
    return false;
  }
  GlueContext ctx{md, par, cb, [this](const std::string& s) { Log(s); }, errorMessage};
  vcgext::StagePeakMemoryMb();  // the filter's stages measure their own peak memory from here
  try {
    switch (ID(a)) {
      case FP_COMPUTE_FITMAPS: return ApplyFitmaps(ctx);
      case FP_QUAD_SIMPLIFICATION: return ApplyQuad(ctx);
      case FP_FIT_AND_BAKE: return ApplyFit(ctx);
      case FP_LOOP_REFINE: return ApplyLoopRefine(ctx);
      case FP_LOOP_SNAP: return ApplyLoopSnap(ctx);
      case FP_LOOP_CURVATURE: return ApplyLoopCurvature(ctx);
    }
  } catch (const std::exception& e) {
    return ctx.Fail(std::string("internal error: ") + e.what());
  }
  return ctx.Fail("unknown filter");
}
