#pragma once
/// \file fit_internal.h
/// Helpers shared by the fit and bake sources (not public API).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Sparse>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/progress.h"
#include "vcg_ext/fit/cc_fit.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext {
namespace fitdetail {

/// TangentDistance: every how-many-th reference vertex gets a row (FitParams::maxDataRows; 1 =
/// every one). The fit's rows and its memory estimate both use it.
inline int DataStride(const FitParams& p, int refVertices) {
  return p.maxDataRows > 0 && refVertices > p.maxDataRows ? (refVertices + p.maxDataRows - 1) / p.maxDataRows : 1;
}

/// Area of the limit patch `f`, from an n×n tessellation.
double PatchArea(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int f, int n);
/// Projection phi of p onto the reference: nearest hit of the line p ± t·n (|t| <= maxDist),
/// else the closest reference point within maxDist. Returns false (target = p) when neither
/// exists; `rayHit` says whether the ray found it.
bool Project(const EmbreeScene& scene, const Vec3& p, const Vec3& n, double maxDist, Vec3& target, bool* rayHit);

/// Projection along the unit limit normal n that skips wrongly oriented sheets: the nearest hit
/// of the line p ± t·n (|t| <= maxDist) on a reference triangle whose normal `refN[face]` agrees
/// with n (dot >= 0). A hit on a triangle facing the other way is the far side of a thin part
/// (an ear seen through itself) and is passed through (up to 8 layers per side). Hit.t is signed
/// (negative behind p). Invalid when no such hit exists.
EmbreeScene::Hit IntersectLineOriented(const EmbreeScene& scene, const std::vector<Vec3>& refN, const Vec3& p,
                                       const Vec3& n, double maxDist);

/// Limit point and unit normal at (f,u,v). Where the tangents are degenerate (e.g. smooth
/// valence-2 boundary corners) the normal is taken 1e-4 inside the patch; zero if still degenerate.
Vec3 LimitPointNormal(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int f, double u, double v, Vec3* n);

/// Exact limit stencil of one fixed sample row (position and first derivatives).
struct StencilRow {
  std::vector<int> idx;
  std::vector<double> w, du, dv;
};

/// The tangent-distance iterations of FitCatmullClark (FitMethod::TangentDistance, see cc_fit.h).
/// `rows` holds the fixed patch samples [0, nS) followed by the vertex rows of system (1); `rowFace`
/// is the face each row lies in and `rowWeight` its weight. X (nV×3) is the start and, on return,
/// the best iterate. Fills rmsPerIteration, dataRmsPerIteration, rayMissFraction, iterations and
/// the timings of `res`. `LtL` (LaplacianNormalMatrix, or empty when smoothWeight = 0) adds the
/// control-net smoothness term μ·|L X|², μ = smoothWeight · mean diagonal. Returns an error
/// message or "".
std::string FitTangentDistance(const LimitSurface& ls, const TriData& ref, const EmbreeScene& scene,
                               const FitParams& p, const std::vector<StencilRow>& rows,
                               const std::vector<int>& rowFace, const std::vector<double>& rowWeight, int nS,
                               double maxDist, const Eigen::SparseMatrix<double>& LtL, Eigen::MatrixXd& X,
                               FitResult& res, Progress& prog);

/// Project → solve stopping rule shared by both fit methods: keeps X as `best` when `obj`
/// improves on `bestObj`; returns true when the iterations should stop (no improvement — the
/// previous iterate is kept —, an improvement below minImprovement, or the last iteration).
inline bool StopIterating(double obj, double& bestObj, const Eigen::MatrixXd& X, Eigen::MatrixXd& best,
                          const FitParams& p, int it) {
  if (!(obj < bestObj)) return true;
  const bool enough = bestObj - obj < p.minImprovement * bestObj;
  bestObj = obj;
  best = X;
  return enough || it == p.maxIterations;
}

/// LᵀL of the uniform (umbrella) Laplacian L of the control net over its quad edges (nV×nV): the
/// normal matrix of the smoothness term μ·|L X|² (FitParams::smoothWeight).
Eigen::SparseMatrix<double> LaplacianNormalMatrix(const QuadData& control);

}  // namespace fitdetail
}  // namespace vcgext
