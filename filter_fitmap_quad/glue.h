#pragma once
/// \file glue.h
/// What every filter's glue gets: the document, its parameters, the progress callback, a log
/// sink and an error slot. Each filter's glue lives in its own glue_<feature>.cpp and only
/// converts parameters -> Params, calls vcg_ext, reports.
#include <common/interfaces.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace fitmapquad {

struct GlueContext {
  MeshDocument& md;
  const RichParameterList& par;
  vcg::CallBackPos* cb;
  std::function<void(const std::string&)> log;
  QString& error;
  /// Records an error for the GUI/meshlabserver and the log; returns false for `return Fail(..)`.
  bool Fail(const std::string& msg) {
    error = QString::fromStdString(msg);
    log("Error: " + msg);
    return false;
  }
};

/// Wall time of the pipeline stages that produced a layer, carried from layer to layer as a
/// per-mesh attribute so the final report can list every stage.
using StageTimes = std::vector<std::pair<std::string, double>>;
StageTimes GetStageTimes(CMeshO& m);
void SetStageTimes(CMeshO& m, const StageTimes& t);

// Compute Fitmaps (glue_fitmaps.cpp)
void InitFitmapsParams(MeshDocument& md, RichParameterList& par);
bool ApplyFitmaps(GlueContext& ctx);
/// The tau the layer's FitmapS/FitmapM attributes were computed with (negative: none).
double GetFitmapTau(CMeshO& m);
void SetFitmapTau(CMeshO& m, double tau);

// Fitmap Quad Simplification (glue_quad.cpp)
void InitQuadParams(MeshDocument& md, RichParameterList& par);
bool ApplyQuad(GlueContext& ctx);
// Fit Catmull-Clark Surface and Bake Displacement (glue_fit.cpp)
void InitFitParams(MeshDocument& md, RichParameterList& par);
bool ApplyFit(GlueContext& ctx);
// Loop Surrogate: Refine Surface / Snap Points / Curvature (glue_loop.cpp)
void InitLoopRefineParams(MeshDocument& md, RichParameterList& par);
bool ApplyLoopRefine(GlueContext& ctx);
void InitLoopSnapParams(MeshDocument& md, RichParameterList& par);
bool ApplyLoopSnap(GlueContext& ctx);
void InitLoopCurvatureParams(MeshDocument& md, RichParameterList& par);
bool ApplyLoopCurvature(GlueContext& ctx);

}  // namespace fitmapquad
