// The plugin class for MeshLab's 2022.02+ interface (FilterPlugin). Same filters, parameters and
// messages as ../filter_fitmap_quad.cpp (MeshLab 2020.09): an error is an MLException carrying the
// message MeshLab 2020.09 shows, which PyMeshLab raises as PyMeshLabException.
#include "filter_fitmap_quad_2025.h"

#include <exception>

#include <common/mlexception.h>

#include "../filter_table.h"
#include "../glue.h"
#include "vcg_ext/core/input_prep.h"

using namespace fitmapquad;

FilterFitmapQuadPlugin::FilterFitmapQuadPlugin() {
  // compute on the float coordinates MeshLab 2020.09 reads, so both plugins give the same cages
  // (vcg_ext/core/input_prep.h, CoordinatePrecision)
  vcgext::SetInputCoordinatePrecision(vcgext::CoordinatePrecision::Float);
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

int FilterFitmapQuadPlugin::postCondition(const QAction* a) const { return PostConditionOf(ID(a)); }

RichParameterList FilterFitmapQuadPlugin::initParameterList(const QAction* a, const MeshDocument& md) {
  RichParameterList par;
  InitParamsOf(ID(a), md, par);
  return par;
}

std::map<std::string, QVariant> FilterFitmapQuadPlugin::applyFilter(const QAction* a, const RichParameterList& par,
                                                                    MeshDocument& md, unsigned int& /*postConditionMask*/,
                                                                    vcg::CallBackPos* cb) {
  if (!Spec(ID(a))) wrongActionCalled(a);
  QString error;
  GlueContext ctx{md, par, cb, [this](const std::string& s) { log(s); }, error};
  bool ok = false;
  try {
    ok = ApplyOf(ID(a), ctx);
  } catch (const MLException&) {
    throw;
  } catch (const std::exception& e) {
    ctx.Fail(std::string("internal error: ") + e.what());
  }
  if (!ok) throw MLException(error.isEmpty() ? QString("unknown filter") : error);
  std::map<std::string, QVariant> out;
  for (const auto& [k, v] : ctx.values) out[k] = QVariant(v);
  return out;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterFitmapQuadPlugin)
