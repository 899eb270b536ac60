// Helpers shared by the glue files.
#include "glue.h"

namespace fitmapquad {

namespace {
const char* kStageTimesAttr = "FitmapQuadStageTimes";
const char* kTauAttr = "FitmapQuadTau";
}

double GetFitmapTau(CMeshO& m) {
  auto h = vcg::tri::Allocator<CMeshO>::FindPerMeshAttribute<double>(m, kTauAttr);
  if (!vcg::tri::Allocator<CMeshO>::IsValidHandle<double>(m, h)) return -1;
  return h();
}

void SetFitmapTau(CMeshO& m, double tau) {
  auto h = vcg::tri::Allocator<CMeshO>::GetPerMeshAttribute<double>(m, kTauAttr);
  h() = tau;
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
