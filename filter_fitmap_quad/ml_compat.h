#pragma once
/// \file ml_compat.h
/// The few places where MeshLab's plugin API differs between the two interfaces this plugin is
/// built for, so the glue_*.cpp files are shared:
///   FITMAP_MESHLAB_API == 2020: MeshLab 2020.09 (MeshFilterInterface, Debian 12's meshlab),
///   FITMAP_MESHLAB_API == 2025: MeshLab 2022.02+ (FilterPlugin; built against 2025.07 for
///                               PyMeshLab 2025.7, MESHLAB_SCALAR=double).
#ifndef FITMAP_MESHLAB_API
#define FITMAP_MESHLAB_API 2020
#endif

#if FITMAP_MESHLAB_API >= 2022
#include <common/plugins/interfaces/filter_plugin.h>
#include <QFileInfo>
#include <QImage>
#else
#include <common/interfaces.h>
#endif

#include <string>
#include <vector>

namespace fitmapquad {

#if FITMAP_MESHLAB_API >= 2022
using PluginBase = FilterPlugin;
#else
using PluginBase = MeshFilterInterface;
#endif

/// The document's layers, in order.
inline std::vector<const MeshModel*> Layers(const MeshDocument& md) {
  std::vector<const MeshModel*> out;
#if FITMAP_MESHLAB_API >= 2022
  for (const MeshModel& m : md.meshIterator()) out.push_back(&m);
#else
  for (const MeshModel* m : md.meshList) out.push_back(m);
#endif
  return out;
}

/// A layer parameter whose default is `m` (the current layer when null).
inline RichMesh MeshParam(const char* name, const MeshModel* m, const MeshDocument& md, const QString& desc,
                          const QString& tip) {
#if FITMAP_MESHLAB_API >= 2022
  return RichMesh(name, m ? m->id() : 0, &md, desc, tip);
#else
  return RichMesh(name, const_cast<MeshModel*>(m), const_cast<MeshDocument*>(&md), desc, tip);
#endif
}

/// The layer a mesh parameter names (null when there is none).
inline MeshModel* GetMeshParam(MeshDocument& md, const RichParameterList& par, const char* name) {
#if FITMAP_MESHLAB_API >= 2022
  return md.getMesh(par.getMeshId(name));
#else
  (void)md;
  return par.getMesh(name);
#endif
}

inline void UpdateBoxAndNormals(MeshModel& m) {
#if FITMAP_MESHLAB_API >= 2022
  m.updateBoxAndNormals();
#else
  m.UpdateBoxAndNormals();
#endif
}

/// Attaches the texture file `path` to the layer. 2020.09 loads it from cm.textures (the full
/// path); 2022.02+ keeps the image in the MeshModel under its file name, which is what saving
/// the layer writes next to the mesh (and what the .mtl names).
inline void AddTexture(MeshModel& m, const std::string& path) {
#if FITMAP_MESHLAB_API >= 2022
  const QString file = QString::fromStdString(path);
  m.addTexture(QFileInfo(file).fileName().toStdString(), QImage(file));
#else
  m.cm.textures.push_back(path);
#endif
}

}  // namespace fitmapquad
