// The plugin class for MeshLab's 2022.02+ interface (FilterPlugin). Same filters, parameters and
// messages as ../filter_fitmap_quad.cpp (MeshLab 2020.09): an error is an MLException carrying the
// message MeshLab 2020.09 shows, which PyMeshLab raises as PyMeshLabException.
#include "filter_fitmap_quad_2025.h"

#include <exception>

#include <common/mlexception.h>

#include "../filter_table.h"
#include "../glue.h"
#include "vcg_ext/core/memory.h"

using namespace fitmapquad;

FilterFitmapQuadPlugin::FilterFitmapQuadPlugin() {
  for (const auto& f : AllFilters()) {
    typeList.push_back(f.id);
    actionList.push_back(new QAction(QString(f.name), this));
  }
}

FilterFitmapQuadPlugin::~FilterFitmapQuadPlugin() = default;

QString FilterFitmapQuadPlugin::filterName(ActionIDType id) const {
  const FilterSpec* s = Spec(id);
  return s ? QString(s->name) : QString("unknown filter");
}

QString FilterFitmapQuadPlugin::pythonFilterName(ActionIDType id) const {
  const FilterSpec* s = Spec(id);
  return s ? QString(s->pythonName) : FilterPlugin::pythonFilterName(id);
}

QString FilterFitmapQuadPlugin::filterInfo(ActionIDType id) const {
  const FilterSpec* s = Spec(id);
  return s ? QString(s->info) : QString();
}

FilterPlugin::FilterClass FilterFitmapQuadPlugin::getClass(const QAction* a) const {
  const FilterSpec* s = Spec(ID(a));
  return s ? FilterClass(s->classes) : FilterPlugin::Remeshing;
}

FilterPlugin::FilterArity FilterFitmapQuadPlugin::filterArity(const QAction*) const { return SINGLE_MESH; }

int FilterFitmapQuadPlugin::getPreConditions(const QAction*) const { return MeshModel::MM_NONE; }

int FilterFitmapQuadPlugin::postCondition(const QAction* a) const {
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

RichParameterList FilterFitmapQuadPlugin::initParameterList(const QAction* a, const MeshDocument& md) {
  RichParameterList par;
  switch (ID(a)) {
    case FP_COMPUTE_FITMAPS: InitFitmapsParams(md, par); break;
    case FP_QUAD_SIMPLIFICATION: InitQuadParams(md, par); break;
    case FP_FIT_AND_BAKE: InitFitParams(md, par); break;
    case FP_LOOP_REFINE: InitLoopRefineParams(md, par); break;
    case FP_LOOP_SNAP: InitLoopSnapParams(md, par); break;
    case FP_LOOP_CURVATURE: InitLoopCurvatureParams(md, par); break;
  }
  return par;
}

std::map<std::string, QVariant> FilterFitmapQuadPlugin::applyFilter(const QAction* a, const RichParameterList& par,
                                                                    MeshDocument& md, unsigned int& /*postConditionMask*/,
                                                                    vcg::CallBackPos* cb) {
  if (md.mm() == nullptr) {
    log("Error: no current layer");
    throw MLException("no current layer");
  }
  QString error;
  GlueContext ctx{md, par, cb, [this](const std::string& s) { log(s); }, error};
  vcgext::StagePeakMemoryMb();  // the filter's stages measure their own peak memory from here
  bool ok = false;
  try {
    switch (ID(a)) {
      case FP_COMPUTE_FITMAPS: ok = ApplyFitmaps(ctx); break;
      case FP_QUAD_SIMPLIFICATION: ok = ApplyQuad(ctx); break;
      case FP_FIT_AND_BAKE: ok = ApplyFit(ctx); break;
      case FP_LOOP_REFINE: ok = ApplyLoopRefine(ctx); break;
      case FP_LOOP_SNAP: ok = ApplyLoopSnap(ctx); break;
      case FP_LOOP_CURVATURE: ok = ApplyLoopCurvature(ctx); break;
      default: wrongActionCalled(a);
    }
  } catch (const MLException&) {
    throw;
  } catch (const std::exception& e) {
    ctx.Fail(std::string("internal error: ") + e.what());
  }
  if (!ok) throw MLException(error.isEmpty() ? QString("unknown filter") : error);
  return {};
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterFitmapQuadPlugin)
