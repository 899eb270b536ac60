#pragma once
/// \file filter_fitmap_quad_2025.h
/// The same six filters as ../filter_fitmap_quad.h for MeshLab's 2022.02+ plugin interface
/// (FilterPlugin), i.e. MeshLab 2025.07 and PyMeshLab 2025.7. Built with
/// -DFITMAP_MESHLAB_API=2025 (build-2025, scripts/setup_pymeshlab.sh). Glue shared with 2020.09:
/// ../glue_*.cpp, ../filter_specs.cpp; the API differences are in ../ml_compat.h.
#include <QObject>
#include <common/plugins/interfaces/filter_plugin.h>

class FilterFitmapQuadPlugin : public QObject, public FilterPlugin {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
  Q_INTERFACES(FilterPlugin)

 public:
  FilterFitmapQuadPlugin();
  ~FilterFitmapQuadPlugin() override;

  QString pluginName() const override { return "FilterFitmapQuad"; }
  QString filterName(ActionIDType filter) const override;
  QString pythonFilterName(ActionIDType filter) const override;
  QString filterInfo(ActionIDType filter) const override;
  FilterClass getClass(const QAction* a) const override;
  FilterArity filterArity(const QAction* a) const override;
  int getPreConditions(const QAction* a) const override;
  int postCondition(const QAction* a) const override;
  RichParameterList initParameterList(const QAction* a, const MeshDocument& md) override;
  std::map<std::string, QVariant> applyFilter(const QAction* a, const RichParameterList& par,
                                              MeshDocument& md, unsigned int& postConditionMask,
                                              vcg::CallBackPos* cb) override;
};
