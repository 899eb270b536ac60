// Helpers shared by the glue files.
#include "glue.h"

namespace fitmapquad {

namespace {
const char* kStageTimesAttr = "FitmapQuadStageTimes";
}

StageTimes GetStageTimes(CMeshO& m) {
  auto h = vcg::tri::Allocator<CMeshO>::FindPerMeshAttribute<StageTimes>(m, kStageTimesAttr);
  if (!vcg::tri::Allocator<CMeshO>::IsValidHandle<StageTimes>(m, h)) return {};
  return h();
}

void SetStageTimes(CMeshO& m, const StageTimes& t) {
  auto h = vcg::tri::Allocator<CMeshO>::GetPerMeshAttribute<StageTimes>(m, kStageTimesAttr);
  h() = t;
}

}  // namespace fitmapquad
