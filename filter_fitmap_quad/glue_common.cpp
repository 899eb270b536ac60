// Helpers shared by the glue files.
#include "glue.h"

namespace fitmapquad {

namespace {
const char* kStageTimesAttr = "FitmapQuadStageTimes";
const char* kStageMemoryAttr = "FitmapQuadStageMemory";

std::vector<std::pair<std::string, double>> GetStageValues(CMeshO& m, const char* name) {
  using Values = std::vector<std::pair<std::string, double>>;
  auto h = vcg::tri::Allocator<CMeshO>::FindPerMeshAttribute<Values>(m, name);
  if (!vcg::tri::Allocator<CMeshO>::IsValidHandle<Values>(m, h)) return {};
  return h();
}

void SetStageValues(CMeshO& m, const char* name, const std::vector<std::pair<std::string, double>>& v) {
  auto h = vcg::tri::Allocator<CMeshO>::GetPerMeshAttribute<std::vector<std::pair<std::string, double>>>(m, name);
  h() = v;
}
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

StageTimes GetStageTimes(CMeshO& m) { return GetStageValues(m, kStageTimesAttr); }
void SetStageTimes(CMeshO& m, const StageTimes& t) { SetStageValues(m, kStageTimesAttr, t); }
StageMemory GetStageMemory(CMeshO& m) { return GetStageValues(m, kStageMemoryAttr); }
void SetStageMemory(CMeshO& m, const StageMemory& s) { SetStageValues(m, kStageMemoryAttr, s); }

}  // namespace fitmapquad
