#include "vcg_ext/subdiv/subdivide_once.h"

#include <opensubdiv/far/primvarRefiner.h>

#include "vcg_ext/subdiv/limit_surface.h"
#include "vcg_ext/subdiv/osd_refiner.h"

namespace vcgext {

namespace {
namespace osd = OpenSubdiv;

// A position as Far::PrimvarRefiner interpolates it.
struct Point {
  Vec3 p = Vec3::Zero();
  void Clear(void* = nullptr) { p.setZero(); }
  void AddWithWeight(const Point& src, double w) { p += w * src.p; }
};
}  // namespace

std::string SubdivideOnce(const PolyData& p, QuadData& out) {
  out.V.clear();
  out.F.clear();
  std::vector<int> sizes, verts;
  for (const auto& f : p.F) {
    sizes.push_back(int(f.size()));
    verts.insert(verts.end(), f.begin(), f.end());
  }
  // The limit surface's own checks (a face or vertex above its valence limit included), so
  // that Far refines only what the fit can evaluate, under the same rules.
  const LimitSurfaceOptions opt;
  const std::string err = LimitSurface::CheckTopology(int(p.V.size()), sizes, verts, opt);
  if (!err.empty()) return err;
  const auto refiner = subdiv_detail::CreateRefiner(int(p.V.size()), sizes, verts, opt);
  if (!refiner) return "OpenSubdiv could not build the control mesh's topology";
  refiner->RefineUniform(osd::Far::TopologyRefiner::UniformOptions(1));

  const osd::Far::TopologyLevel& level = refiner->GetLevel(1);
  std::vector<Point> src(p.V.size()), dst(size_t(level.GetNumVertices()));
  for (size_t i = 0; i < p.V.size(); ++i) src[i].p = p.V[i];
  osd::Far::PrimvarRefinerReal<double>(*refiner).Interpolate(1, src, dst);
  out.V.reserve(dst.size());
  for (const Point& d : dst) out.V.push_back(d.p);
  out.F.reserve(size_t(level.GetNumFaces()));
  for (int f = 0; f < level.GetNumFaces(); ++f) {
    const osd::Far::ConstIndexArray fv = level.GetFaceVertices(f);
    out.F.push_back({fv[0], fv[1], fv[2], fv[3]});
  }
  return "";
}

}  // namespace vcgext
