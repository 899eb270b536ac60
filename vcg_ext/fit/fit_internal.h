#pragma once
/// \file fit_internal.h
/// Helpers shared by the fit and bake sources (not public API).
#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext {
namespace fitdetail {

/// Area of the limit patch `f`, from an n×n tessellation.
double PatchArea(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int f, int n);
/// Projection phi of p onto the reference: nearest hit of the line p ± t·n (|t| <= maxDist),
/// else the closest reference point within maxDist. Returns false (target = p) when neither
/// exists; `rayHit` says whether the ray found it.
bool Project(const EmbreeScene& scene, const Vec3& p, const Vec3& n, double maxDist, Vec3& target, bool* rayHit);

/// Limit point and unit normal at (f,u,v). Where the tangents are degenerate (e.g. smooth
/// valence-2 boundary corners) the normal is taken 1e-4 inside the patch; zero if still degenerate.
Vec3 LimitPointNormal(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int f, double u, double v, Vec3* n);

}  // namespace fitdetail
}  // namespace vcgext
