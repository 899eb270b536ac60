#include "filter_fitmap_quad.h"

#include <exception>

#include "filter_table.h"
#include "glue.h"

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

int FilterFitmapQuadPlugin::postCondition(QAction* a) const { return PostConditionOf(ID(a)); }

void FilterFitmapQuadPlugin::initParameterSet(QAction* a, MeshDocument& md, RichParameterList& par) {
  InitParamsOf(ID(a), md, par);
}

bool FilterFitmapQuadPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                         vcg::CallBackPos* cb) {
  GlueContext ctx{md, par, cb, [this](const std::string& s) { Log(s); }, errorMessage};
  try {
    return ApplyOf(ID(a), ctx);
  } catch (const std::exception& e) {
    return ctx.Fail(std::string("internal error: ") + e.what());
  }
}
