// Glue for "Compute Fitmaps" (paper §3.1): parameters -> vcgext::FitmapParams -> attributes.
#include <QStringList>

#include <chrono>

#include "filter_table.h"
#include "glue.h"
#include "vcg_ext/core/quality.h"
#include "vcg_ext/fitmaps/fitmaps.h"

namespace fitmapquad {

void InitFitmapsParams(const MeshDocument& /*md*/, RichParameterList& par) {
  const vcgext::FitmapParams d;
  par.addParam(RichFloat(param::kTau, float(d.tauPercent), "Tolerance tau (%)",
                         "M-fitmap: largest tolerated share of flipped (un-hit) triangles in a "
                         "neighbourhood, in percent. Higher values allow larger patches."));
  par.addParam(RichInt(param::kNumRadii, d.numRadii, "Number of radii",
                       "Neighbourhood radii r_0..r_h (paper: 9, i.e. h = 8), exponentially spaced "
                       "from the average edge length to the largest radius."));
  par.addParam(RichFloat(param::kMaxRadiusPerc, float(d.maxRadiusPercent),
                         "Largest radius (% of bbox diagonal)",
                         "r_h in percent of the bounding-box diagonal (paper: 25%)."));
  par.addParam(RichEnum(param::kChannel, 0, QStringList() << "S-fitmap" << "M-fitmap",
                        "Channel shown", "Which Fitmap is copied to the vertex quality."));
  par.addParam(RichBool(param::kColorize, true, "Colorize",
                        "Colour vertices by the shown channel (quality ramp, 1-99 percentiles)."));
  par.addParam(RichInt(param::kWorkingFaces, kDefaultFitmapsWorkingFaces, "Working resolution (triangles, 0 = full)",
                       "Bounded cost on dense scans (paper §4): a layer with more triangles is "
                       "decimated to this many (vcglib's quadric edge collapse), the Fitmaps are "
                       "computed there and interpolated to every vertex of the layer. 0 computes "
                       "them at every vertex. Fast mode only."));
  par.addParam(RichEnum(param::kMode, 0, QStringList() << "Fast" << "Reference (slow, literal paper)",
                        "Computation mode",
                        "Fast: bounded work per vertex. Reference: the paper's literal O(n·|B|) "
                        "computation (minutes on large meshes)."));
}

bool ApplyFitmaps(GlueContext& ctx) {
  MeshModel& mm = *ctx.md.mm();
  vcgext::FitmapParams p;
  p.tauPercent = ctx.par.getFloat(param::kTau);
  p.numRadii = ctx.par.getInt(param::kNumRadii);
  p.maxRadiusPercent = ctx.par.getFloat(param::kMaxRadiusPerc);
  p.workingFaces = ctx.par.getInt(param::kWorkingFaces);
  if (p.workingFaces < 0) return ctx.Fail("the working resolution must be >= 0 triangles");
  p.mode = ctx.par.getEnum(param::kMode) == 1 ? vcgext::FitmapParams::Mode::Reference
                                               : vcgext::FitmapParams::Mode::Fast;
  if (!(p.tauPercent >= 0 && p.tauPercent <= 100)) return ctx.Fail("tau must be in [0, 100] percent");
  if (p.numRadii < 2 || p.numRadii > 64) return ctx.Fail("number of radii must be in [2, 64]");
  if (!(p.maxRadiusPercent > 0 && p.maxRadiusPercent <= 100))
    return ctx.Fail("largest radius must be in (0, 100] percent of the bbox diagonal");

  auto t0 = std::chrono::steady_clock::now();
  vcgext::FitmapResult r = vcgext::ComputeFitmaps(mm.cm, p, ctx.cb);
  if (!r.error.empty()) return ctx.Fail("Compute Fitmaps: " + r.error);
  for (const auto& n : r.notes) ctx.log("Compute Fitmaps: " + n);
  for (const auto& n : r.warnings) ctx.log("Warning: Compute Fitmaps: " + n);
  WarnIfNotSimilarity(ctx, mm, "Compute Fitmaps");
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  SetFitmapTau(mm.cm, p.tauPercent);
  SetStageTimes(mm.cm, {{"fitmaps", secs}});
  SetStageMemory(mm.cm, {{"fitmaps", vcgext::StagePeakMemoryMb()}});
  const bool showM = ctx.par.getEnum(param::kChannel) == 1;
  mm.updateDataMask(MeshModel::MM_VERTQUALITY);
  vcgext::QualityFromAttribute(mm.cm, showM ? vcgext::kFitmapMAttr : vcgext::kFitmapSAttr);
  std::pair<double, double> range{0, 0};
  if (ctx.par.getBool(param::kColorize)) {
    mm.updateDataMask(MeshModel::MM_VERTCOLOR);
    range = vcgext::ColorizeQuality(mm.cm);
  }
  if (r.workingFaces > 0)
    ctx.log("Compute Fitmaps: computed at the working resolution (" + std::to_string(r.workingFaces) +
            " triangles; decimation " + std::to_string(r.secondsDecimate) + " s) and interpolated to the " +
            std::to_string(mm.cm.vn) + " vertices (" + std::to_string(r.secondsTransfer) + " s)");
  char buf[512];
  snprintf(buf, sizeof buf,
           "Compute Fitmaps (%s mode): %d vertices in %.2f s; radii %.4g..%.4g; showing %s "
           "(colour ramp %.4g..%.4g)",
           p.mode == vcgext::FitmapParams::Mode::Fast ? "fast" : "reference", mm.cm.vn, secs,
           r.radii.empty() ? 0.0 : r.radii.front(), r.radii.empty() ? 0.0 : r.radii.back(),
           showM ? "M-fitmap" : "S-fitmap", range.first, range.second);
  ctx.log(buf);
  ctx.Value("vertices", mm.cm.vn);
  ctx.Value("working_faces", r.workingFaces);
  ctx.Value("seconds", secs);
  ctx.Value("min_radius", r.radii.empty() ? 0.0 : r.radii.front());
  ctx.Value("max_radius", r.radii.empty() ? 0.0 : r.radii.back());
  return true;
}

}  // namespace fitmapquad
