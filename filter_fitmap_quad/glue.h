#pragma once
/// \file glue.h
/// What every filter's glue gets: the document, its parameters, the progress callback, a log
/// sink and an error slot. Each filter's glue lives in its own glue_<feature>.cpp and only
/// converts parameters -> Params, calls vcg_ext, reports.
#include "ml_compat.h"

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vcg_ext/core/memory.h"

namespace fitmapquad {

struct GlueContext {
  MeshDocument& md;
  const RichParameterList& par;
  vcg::CallBackPos* cb;
  std::function<void(const std::string&)> log;
  QString& error;
  /// Figures a filter returns to its caller (PyMeshLab 2022.02+ gets them as the dict that
  /// `MeshSet.apply_filter` returns; MeshLab 2020.09's interface has no return values).
  std::map<std::string, double> values = {};
  void Value(const std::string& key, double v) { values[key] = v; }
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
/// Peak resident memory (MB) of the same stages (vcgext::StagePeakMemoryMb), carried the same way.
using StageMemory = vcgext::StageMemory;
StageMemory GetStageMemory(CMeshO& m);
void SetStageMemory(CMeshO& m, const StageMemory& s);

/// Layer matrices (CMeshO::Tr: MeshLab's Align tool, or a Transform filter run without freezing
/// the matrix, set it; MeshLab draws the layer through it). The filters compute in a layer's own
/// coordinates, like MeshLab's; a layer they add carries the matrix of the layer its coordinates
/// are in, so that it shows where that layer shows (docs/robustness.md "Layer matrices").
Eigen::Matrix4d LayerMatrix(const MeshModel& m);
/// `tr` in the layer's matrix type (Matrix44m: float in MeshLab 2020.09, double in 2022.02+).
Matrix44m VcgMatrix(const Eigen::Matrix4d& tr);
/// The matrix that takes `from`'s own coordinates to `to`'s (Tr_to^-1 Tr_from): what a two-layer
/// filter applies to one layer's points to use them with the other's; the identity when the two
/// layers have the same matrix. False when `to`'s matrix cannot be inverted.
bool RelativeMatrix(const MeshModel& from, const MeshModel& to, Eigen::Matrix4d& rel);
/// Logs a warning when `m`'s matrix is not a similarity (a rotation times one scale, plus a
/// translation): the filter's distances are then in the layer's own coordinates, not in the ones
/// MeshLab draws. `filter` prefixes the message.
void WarnIfNotSimilarity(GlueContext& ctx, const MeshModel& m, const std::string& filter);

/// Default working resolutions (docs/multires.md "The rule"), in triangles: "Compute Fitmaps"
/// runs on M'_F (the paper's §4 size, about 100K triangles; bunny00's 75k stays as it is), and
/// "Fitmap Quad Simplification" starts from M'_S, decimated from M'_F (one decimation of a dense
/// input serves both filters).
constexpr int kDefaultFitmapsWorkingFaces = 100000;
constexpr int kDefaultWorkingFaces = 40000;
/// An input above the working resolution is first simplified from a coarser start
/// (vcgext::SimplifyFromWorkingStart; docs/multires.md "A coarser first start").
constexpr int kDefaultFirstWorkingFaces = 10000;
/// A smaller input starts the simplification from its midpoint refinement (docs/robustness.md).
constexpr int kMinWorkingFaces = 1000;
/// An input with a vertex of higher valence starts from an isotropic remesh (decimate.h).
constexpr int kMaxStartValence = 24;

// By filter id, for both plugin classes (dispatch.cpp): the layers the filter changes
// (postCondition mask), its parameters, its run (false with ctx.error set on failure: no
// current layer, an unknown id, or the filter's own error).
int PostConditionOf(int id);
void InitParamsOf(int id, const MeshDocument& md, RichParameterList& par);
bool ApplyOf(int id, GlueContext& ctx);

// Compute Fitmaps (glue_fitmaps.cpp)
void InitFitmapsParams(const MeshDocument& md, RichParameterList& par);
bool ApplyFitmaps(GlueContext& ctx);
/// The tau the layer's FitmapS/FitmapM attributes were computed with (negative: none).
double GetFitmapTau(CMeshO& m);
void SetFitmapTau(CMeshO& m, double tau);

// Fitmap Quad Simplification (glue_quad.cpp)
void InitQuadParams(const MeshDocument& md, RichParameterList& par);
bool ApplyQuad(GlueContext& ctx);
// Fit Catmull-Clark Surface and Bake Displacement (glue_fit.cpp)
void InitFitParams(const MeshDocument& md, RichParameterList& par);
bool ApplyFit(GlueContext& ctx);
// Loop Surrogate: Refine Surface / Snap Points / Curvature (glue_loop.cpp)
void InitLoopRefineParams(const MeshDocument& md, RichParameterList& par);
bool ApplyLoopRefine(GlueContext& ctx);
void InitLoopSnapParams(const MeshDocument& md, RichParameterList& par);
bool ApplyLoopSnap(GlueContext& ctx);
void InitLoopCurvatureParams(const MeshDocument& md, RichParameterList& par);
bool ApplyLoopCurvature(GlueContext& ctx);

}  // namespace fitmapquad
