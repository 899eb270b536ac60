// Helpers shared by the glue files.
#include "glue.h"

#include <Eigen/LU>

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

Eigen::Matrix4d LayerMatrix(const MeshModel& m) {
  Eigen::Matrix4d tr;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) tr(i, j) = double(m.cm.Tr.ElementAt(i, j));
  return tr;
}

Matrix44m VcgMatrix(const Eigen::Matrix4d& tr) {
  Matrix44m m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m.ElementAt(i, j) = Matrix44m::ScalarType(tr(i, j));
  return m;
}

bool RelativeMatrix(const MeshModel& from, const MeshModel& to, Eigen::Matrix4d& rel) {
  const Eigen::Matrix4d a = LayerMatrix(from), b = LayerMatrix(to);
  rel.setIdentity();
  if (a == b) return true;
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(b);
  if (!lu.isInvertible()) return false;
  rel = lu.inverse() * a;
  return true;
}

void WarnIfNotSimilarity(GlueContext& ctx, const MeshModel& m, const std::string& filter) {
  const Eigen::Matrix4d tr = LayerMatrix(m);
  const Eigen::Matrix3d a = tr.topLeftCorner<3, 3>();
  const Eigen::Matrix3d ata = a.transpose() * a;
  const double s2 = ata.trace() / 3;
  // A rotation times one scale: A^T A = s^2 I (float matrices: to 1e-5 of s^2).
  const bool similar = tr.row(3) == Eigen::RowVector4d(0, 0, 0, 1) && s2 > 0 &&
                       (ata - s2 * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-5 * s2;
  if (!similar)
    ctx.log("Warning: " + filter + ": layer '" + m.label().toStdString() +
            "' has a transformation matrix that scales unevenly, shears or projects: distances and errors are "
            "in the layer's own coordinates, not in the ones MeshLab draws (freeze the matrix first: Filters > "
            "Normals, Curvatures and Orientation > Matrix: Freeze Current Matrix; PyMeshLab apply_matrix_freeze)");
}

}  // namespace fitmapquad
