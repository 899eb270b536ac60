#pragma once
/// \file glue.h
/// What every filter's glue gets: the document, its parameters, the progress callback, a log
/// sink and an error slot. Each filter's glue lives in its own glue_<feature>.cpp and only
/// converts parameters -> Params, calls vcg_ext, reports.
#include <common/interfaces.h>

#include <functional>
#include <string>

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

// Compute Fitmaps (glue_fitmaps.cpp)
void InitFitmapsParams(MeshDocument& md, RichParameterList& par);
bool ApplyFitmaps(GlueContext& ctx);

}  // namespace fitmapquad
