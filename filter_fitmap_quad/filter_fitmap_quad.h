#pragma once
/// \file filter_fitmap_quad.h
/// MeshLab 2020.09 filter plugin: Fitmaps, Fitmap quad simplification, Catmull-Clark fit and
/// displacement bake, Loop surrogate geometry. Glue only: the algorithms live in vcg_ext/.
#include <QObject>
#include <common/interfaces.h>

class FilterFitmapQuadPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

 public:
  FilterFitmapQuadPlugin();
  ~FilterFitmapQuadPlugin() override;

  QString pluginName() const override { return "FilterFitmapQuad"; }
  QString filterName(FilterIDType filter) const override;
  QString filterInfo(FilterIDType filter) const override;
  FilterClass getClass(QAction* a) override;
  FILTER_ARITY filterArity(QAction* a) const override;
  int getPreConditions(QAction* a) const override;
  int postCondition(QAction* a) const override;
  using MeshFilterInterface::initParameterSet;
  void initParameterSet(QAction* a, MeshDocument& md, RichParameterList& par) override;
  bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                   vcg::CallBackPos* cb) override;
};
