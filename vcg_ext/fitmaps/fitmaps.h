#pragma once
/// \file fitmaps.h
/// S- and M-Fitmaps (Panozzo et al. 2011, §3.1): per-vertex estimates of how well a single
/// cubic patch models the surface around each vertex (S: error growth a^{1/4} of E(r) = a r^4)
/// and how far a patch may extend before normal projection breaks (M: largest radius whose
/// share of un-hit triangles stays below tau).
#include <string>
#include <vector>

#include <vcg/complex/complex.h>
#include <wrap/callback.h>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Parameters of ComputeFitmaps. Lengths are relative to the bounding-box diagonal where noted.
struct FitmapParams {
  enum class Mode {
    Fast,       ///< bounded work per vertex (default); agreement with Reference in README
    Reference,  ///< the paper's literal O(n·|B|) computation (slow: minutes on 75k triangles)
  };
  double tauPercent = 1.0;         ///< tau: tolerated share of flipped (un-hit) triangles, percent
  int numRadii = 9;                ///< number of radii r_0..r_h (paper: h = 8, i.e. 9 radii)
  double maxRadiusPercent = 25.0;  ///< r_h in percent of the bbox diagonal (paper: 1/4 = 25%)
  Mode mode = Mode::Fast;
  unsigned seed = 1;               ///< random sampling seed (results are deterministic per seed)
};

/// Per-vertex results, indexed like the TriData's V (unreferenced vertices: S = 0, M = r_0).
struct FitmapResult {
  std::string error;          ///< non-empty: nothing else is meaningful
  std::vector<double> S;      ///< S-fitmap a^{1/4}, unit 1/length
  std::vector<double> M;      ///< M-fitmap, a radius (absolute length)
  std::vector<double> radii;  ///< the radii used, absolute
  double seconds = 0;         ///< wall time
};

/// Computes both Fitmaps of `m` (paper §3.1.2–3.1.3). `scene` must be built on `m`.
/// Cost: Fast mode O(n · k) with k bounded per vertex; Reference mode O(n · |B|).
FitmapResult ComputeFitmaps(const TriData& m, const EmbreeScene& scene, const FitmapParams& p,
                            vcg::CallBackPos* cb = nullptr);

/// Names of the per-vertex float attributes that hold the results on a vcg mesh.
inline const char* kFitmapSAttr = "FitmapS";
inline const char* kFitmapMAttr = "FitmapM";

/// vcg entry point: validates the layer (see ImportTriangles), computes the Fitmaps and stores
/// them in the per-vertex float attributes FitmapS / FitmapM (created if missing). On error the
/// mesh is untouched and `result.error` says why.
template <class MeshType>
FitmapResult ComputeFitmaps(MeshType& m, const FitmapParams& p, vcg::CallBackPos* cb = nullptr) {
  TriData data;
  ImportReport rep = ImportTriangles(m, data);
  FitmapResult res;
  if (!rep.error.empty()) { res.error = rep.error; return res; }
  EmbreeScene scene(data);
  if (!scene.Ok()) { res.error = scene.Error(); return res; }
  res = ComputeFitmaps(data, scene, p, cb);
  if (!res.error.empty()) return res;
  auto hS = vcg::tri::Allocator<MeshType>::template GetPerVertexAttribute<float>(m, kFitmapSAttr);
  auto hM = vcg::tri::Allocator<MeshType>::template GetPerVertexAttribute<float>(m, kFitmapMAttr);
  size_t i = 0;
  for (auto& v : m.vert) {
    if (v.IsD()) continue;
    hS[v] = float(res.S[i]);
    hM[v] = float(res.M[i]);
    ++i;
  }
  return res;
}

}  // namespace vcgext
