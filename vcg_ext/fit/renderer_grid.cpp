#include "vcg_ext/fit/renderer_grid.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace vcgext {

namespace {
// Blender's corner angle: acos of the dot of the normalized edges leaving the corner.
double CornerAngle(const Vec3& prev, const Vec3& v, const Vec3& next) {
  Vec3 a = prev - v, b = next - v;
  const double la = a.norm(), lb = b.norm();
  if (!(la > 0) || !(lb > 0)) return 0.0;
  return std::acos(std::clamp(a.dot(b) / (la * lb), -1.0, 1.0));
}
}  // namespace

LimitTessellation RendererGrid(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int level) {
  if (level < 1 || level > 8) return {};
  LimitTessellation t = TessellateLimit(ls, ctrl, 1 << level);
  if (t.mesh.F.size() % 2 != 0) return {};
  std::vector<Vec3> acc(t.mesh.V.size(), Vec3::Zero());
  // uniform grid: each cell is the triangle pair (v00, v10, v11), (v00, v11, v01)
  for (size_t k = 0; k + 1 < t.mesh.F.size(); k += 2) {
    const int q[4] = {t.mesh.F[k][0], t.mesh.F[k][1], t.mesh.F[k][2], t.mesh.F[k + 1][2]};
    const auto& V = t.mesh.V;
    Vec3 n = (V[q[2]] - V[q[0]]).cross(V[q[3]] - V[q[1]]);
    const double len = n.norm();
    if (!(len > 0)) continue;
    n /= len;
    for (int c = 0; c < 4; ++c) acc[q[c]] += CornerAngle(V[q[(c + 3) % 4]], V[q[c]], V[q[(c + 1) % 4]]) * n;
  }
  for (size_t v = 0; v < acc.size(); ++v) {
    const double len = acc[v].norm();
    if (len > 0) t.normal[v] = acc[v] / len;  // else keep the limit normal (isolated degenerate cells)
  }
  return t;
}

int GridVertex(const LimitTessellation& t, int f, int i, int j) {
  const int N = t.N;
  const size_t base = size_t(f) * 2 * N * N;
  auto cell = [&](int ci, int cj) { return base + 2 * (size_t(cj) * N + ci); };
  if (i < N && j < N) return t.mesh.F[cell(i, j)][0];
  if (j < N) return t.mesh.F[cell(N - 1, j)][1];            // i == N: v10 of the last cell in the row
  if (i < N) return t.mesh.F[cell(i, N - 1) + 1][2];        // j == N: v01 of the top row's cell
  return t.mesh.F[cell(N - 1, N - 1)][2];                   // (N, N): v11
}

int RendererLevel(const DisplacementAtlas& a) {
  int level = 0;
  for (int R : a.tileR) {
    const int s = R - 1;
    if (s < 1 || (s & (s - 1)) != 0) return 0;
    int k = 0;
    while ((1 << k) < s) ++k;
    level = std::max(level, k);
  }
  return std::max(level, 1);
}

}  // namespace vcgext
