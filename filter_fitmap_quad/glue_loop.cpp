// Glue for the Loop surrogate-geometry filters (Persson et al.): Refine Surface, Snap Points,
// Curvature. Parameters -> vcgext::Loop*Params -> vcg entry points in vcg_ext/loop/loop_vcg.h.
#include <QStringList>

#include <cmath>
#include <set>

#include "filter_table.h"
#include "glue.h"
// (after glue.h: vcglib's algorithms need the mesh types MeshLab's headers bring)
#include <vcg/complex/algorithms/update/position.h>
#include "vcg_ext/core/quality.h"
#include "vcg_ext/loop/loop_vcg.h"

namespace fitmapquad {

namespace {

void AddSurfaceParams(RichParameterList& par) {
  const vcgext::LoopSurfaceParams d;
  par.addParam(RichFloat(param::kCreaseAngle, float(d.creaseAngleDeg), "Crease angle (deg)",
                         "Edges whose dihedral angle exceeds this are hard edges (C2 crease "
                         "curves; vertices with more than two hard edges stay fixed). Boundary "
                         "edges are always hard. 0 disables the angle test."));
  par.addParam(RichBool(param::kUseEdgeSelection, false, "Selected edges are hard",
                        "Also tag the layer's selected edges as hard (e.g. from 'Select Crease "
                        "Edges')."));
}

// Every live vertex of `m` mapped by `tr` (vcglib's, as MeshLab's Freeze Matrix; nothing to do
// for the identity).
void MapVertices(const Eigen::Matrix4d& tr, CMeshO& m) {
  if (tr != Eigen::Matrix4d::Identity()) vcg::tri::UpdatePosition<CMeshO>::Matrix(m, VcgMatrix(tr), false);
}

// Reads the surface parameters; selected face-edges of `m` become extra hard edges.
bool ReadSurfaceParams(GlueContext& ctx, CMeshO& m, vcgext::LoopSurfaceParams& sp) {
  sp.creaseAngleDeg = ctx.par.getFloat(param::kCreaseAngle);
  if (!(sp.creaseAngleDeg >= 0 && sp.creaseAngleDeg <= 180)) {
    ctx.Fail("crease angle must be in [0, 180] degrees");
    return false;
  }
  if (ctx.par.getBool(param::kUseEdgeSelection)) {
    // Vertex indices as ImportTriangles numbers them: live vertices in order.
    std::vector<int> live(m.vert.size(), -1);
    int n = 0;
    for (size_t i = 0; i < m.vert.size(); ++i)
      if (!m.vert[i].IsD()) live[i] = n++;
    std::set<std::pair<int, int>> edges;
    for (const auto& f : m.face) {
      if (f.IsD()) continue;
      for (int k = 0; k < 3; ++k)
        if (f.IsFaceEdgeS(k)) {
          int a = live[vcg::tri::Index(m, f.cV(k))], b = live[vcg::tri::Index(m, f.cV((k + 1) % 3))];
          edges.insert(std::minmax(a, b));
        }
    }
    sp.extraHardEdges.assign(edges.begin(), edges.end());
    ctx.log("Loop Surrogate: " + std::to_string(edges.size()) + " selected edges tagged hard");
  }
  return true;
}

// Fails (and says why) when the layer cannot be read: face references outside its vertices,
// NaN coordinates, empty (ImportTriangles' checks; a point layer without faces is fine here).
bool CheckReadable(GlueContext& ctx, const CMeshO& m, const std::string& prefix) {
  vcgext::TriData t;
  vcgext::ImportReport rep = vcgext::ImportTriangles(m, t, /*allowPolygonal=*/true, /*keepDegenerate=*/true);
  if (!rep.error.empty() && rep.error.find("point cloud") == std::string::npos) return ctx.Fail(prefix + rep.error);
  return true;
}

// The repairs made on the working copy (input_prep.h), one log line each.
void LogWorkingCopy(GlueContext& ctx, const std::string& prefix, const vcgext::LoopVcgReport& rep) {
  for (const auto& n : rep.notes) ctx.log(prefix + n);
  for (const auto& n : rep.warnings) ctx.log("Warning: " + prefix + n);
}

}  // namespace

void InitLoopRefineParams(const MeshDocument& /*md*/, RichParameterList& par) {
  const vcgext::LoopRefineParams d;
  par.addParam(RichEnum(param::kRefineMode, 0, QStringList() << "Adaptive (curvature)" << "Uniform",
                        "Refinement", "Adaptive: split where max principal curvature x area is "
                        "largest. Uniform: split the largest triangles."));
  AddSurfaceParams(par);
  par.addParam(RichBool(param::kInterpolate, false, "Interpolate the control net",
                        "First move the control points so that the limit surface passes through "
                        "the original vertices (S_inf x = x, Krylov solve); cusps are reported."));
  par.addParam(RichInt(param::kTargetFaces, 100000, "Target triangles",
                       "Refinement stops at this many triangles."));
}

bool ApplyLoopRefine(GlueContext& ctx) {
  MeshModel& net = *ctx.md.mm();
  vcgext::LoopSurfaceParams sp;
  if (!ReadSurfaceParams(ctx, net.cm, sp)) return false;
  vcgext::LoopRefineParams rp;
  rp.mode = ctx.par.getEnum(param::kRefineMode) == 1 ? vcgext::LoopRefineParams::Mode::Uniform
                                                     : vcgext::LoopRefineParams::Mode::Adaptive;
  rp.targetFaces = ctx.par.getInt(param::kTargetFaces);
  if (rp.targetFaces < 1 || rp.targetFaces > 50000000) return ctx.Fail("target triangles must be in [1, 5e7]");
  const bool interp = ctx.par.getBool(param::kInterpolate);

  CMeshO out;
  vcgext::LoopVcgReport rep = vcgext::LoopRefineMesh(net.cm, out, sp, interp, rp, ctx.cb);
  if (!rep.error.empty()) return ctx.Fail("Loop Surrogate: Refine Surface: " + rep.error);
  LogWorkingCopy(ctx, "Loop Surrogate: Refine Surface: ", rep);
  WarnIfNotSimilarity(ctx, net, "Loop Surrogate: Refine Surface");
  MeshModel* m = ctx.md.addNewMesh("", net.label() + (interp ? " loop interpolated" : " loop refined"), true);
  m->cm.Tr = net.cm.Tr;
  vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(m->cm, out, false, true);
  UpdateBoxAndNormals(*m);
  char buf[512];
  snprintf(buf, sizeof buf,
           "Loop Surrogate: Refine Surface (%s): %d -> %d triangles in %.2f s (%d passes, %d "
           "insertions, %d crease splits, %d swaps); %d hard edges, %d hard vertices, %d irregular "
           "control faces",
           rp.mode == vcgext::LoopRefineParams::Mode::Adaptive ? "adaptive" : "uniform", net.cm.fn, m->cm.fn,
           rep.refine.seconds, rep.refine.passes, rep.refine.insertions, rep.refine.edgeSplits, rep.refine.swaps,
           rep.hardEdges, rep.hardVertices, rep.irregularFaces);
  ctx.log(buf);
  if (interp) {
    snprintf(buf, sizeof buf,
             "Loop Surrogate: interpolation residual %.3g (relative to the bbox diagonal) after %d "
             "iterations; %d cusp vertices (flipped limit normal), %d folded faces",
             rep.interp.residual, rep.interp.iterations, rep.interp.flippedVertices,
             rep.interp.foldedFaces);
    ctx.log(buf);
  }
  return true;
}

void InitLoopSnapParams(const MeshDocument& md, RichParameterList& par) {
  const MeshModel* other = md.mm();
  for (const MeshModel* m : Layers(md))
    if (m != md.mm() && m->cm.fn > 0) { other = m; break; }
  par.addParam(MeshParam(param::kSurfaceMesh, other, md, "Control net",
                        "The triangle layer whose Loop limit surface the current layer's vertices "
                        "are snapped onto."));
  AddSurfaceParams(par);
}

bool ApplyLoopSnap(GlueContext& ctx) {
  MeshModel& pts = *ctx.md.mm();
  MeshModel* net = GetMeshParam(ctx.md, ctx.par, param::kSurfaceMesh);
  if (!net) return ctx.Fail("the control-net layer is missing");
  if (net == &pts) return ctx.Fail("the control net must be another layer than the points (the current layer)");
  vcgext::LoopSurfaceParams sp;
  if (!ReadSurfaceParams(ctx, net->cm, sp)) return false;
  if (!CheckReadable(ctx, pts.cm, "Loop Surrogate: Snap Points: ")) return false;
  // Snap a copy: the layer is only changed when everything succeeded.
  CMeshO copy;
  vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(copy, pts.cm, false, true);
  if (copy.vn == 0) return ctx.Fail("the layer to snap has no vertices");
  // Snapped in the net's coordinates when the two layers' matrices differ, then mapped back.
  Eigen::Matrix4d toNet, back;
  if (!RelativeMatrix(pts, *net, toNet) || !RelativeMatrix(*net, pts, back))
    return ctx.Fail("Loop Surrogate: Snap Points: a layer's transformation matrix cannot be inverted");
  WarnIfNotSimilarity(ctx, *net, "Loop Surrogate: Snap Points");
  MapVertices(toNet, copy);
  vcgext::LoopVcgReport rep = vcgext::LoopSnapVertices(copy, net->cm, sp);
  if (!rep.error.empty()) return ctx.Fail("Loop Surrogate: Snap Points: " + rep.error);
  MapVertices(back, copy);
  LogWorkingCopy(ctx, "Loop Surrogate: Snap Points: control net: ", rep);
  size_t i = 0;
  pts.updateDataMask(MeshModel::MM_VERTQUALITY);
  for (auto& v : pts.cm.vert) {
    if (v.IsD()) continue;
    v.P() = copy.vert[i].P();
    v.Q() = Scalarm(rep.distances[i]);
    ++i;
  }
  UpdateBoxAndNormals(pts);
  char buf[256];
  snprintf(buf, sizeof buf,
           "Loop Surrogate: Snap Points: %zu vertices moved onto the limit surface; distance mean "
           "%.4g, max %.4g (stored in vertex quality); %d without Newton convergence (fallback used)",
           rep.distances.size(), rep.meanDistance, rep.maxDistance, rep.snapNotConverged);
  ctx.log(buf);
  return true;
}

void InitLoopCurvatureParams(const MeshDocument& /*md*/, RichParameterList& par) {
  par.addParam(RichEnum(param::kCurvatureKind, 0,
                        QStringList() << "Mean" << "Gaussian" << "Max absolute" << "Min principal" << "Max principal",
                        "Curvature", "Which curvature of the limit surface goes to the vertex quality."));
  AddSurfaceParams(par);
  par.addParam(RichBool(param::kColorize, true, "Colorize", "Colour vertices by the curvature (1-99 percentiles)."));
}

bool ApplyLoopCurvature(GlueContext& ctx) {
  MeshModel& m = *ctx.md.mm();
  vcgext::LoopSurfaceParams sp;
  if (!ReadSurfaceParams(ctx, m.cm, sp)) return false;
  const int kind = ctx.par.getEnum(param::kCurvatureKind);
  if (kind < 0 || kind > 4) return ctx.Fail("unknown curvature kind");
  // The layer is read (and its face references checked) before copying it: a corrupt file's
  // out-of-range references would crash vcglib's copy.
  if (!CheckReadable(ctx, m.cm, "Loop Surrogate: Curvature: ")) return false;
  // Compute on a copy so a failure leaves the layer (and whether it has quality) untouched.
  CMeshO copy;
  vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(copy, m.cm, false, true);
  vcgext::LoopVcgReport rep = vcgext::LoopCurvatureToQuality(copy, sp, vcgext::LoopCurvatureKind(kind));
  if (!rep.error.empty()) return ctx.Fail("Loop Surrogate: Curvature: " + rep.error);
  LogWorkingCopy(ctx, "Loop Surrogate: Curvature: ", rep);
  WarnIfNotSimilarity(ctx, m, "Loop Surrogate: Curvature");
  m.updateDataMask(MeshModel::MM_VERTQUALITY);
  size_t i = 0;
  for (auto& v : m.cm.vert)
    if (!v.IsD()) v.Q() = copy.vert[i++].Q();
  std::pair<double, double> range{0, 0};
  if (ctx.par.getBool(param::kColorize)) {
    m.updateDataMask(MeshModel::MM_VERTCOLOR);
    range = vcgext::ColorizeQuality(m.cm);
  }
  char buf[256];
  snprintf(buf, sizeof buf, "Loop Surrogate: Curvature: %d vertices, %d hard edges, %d hard vertices; colour ramp %.4g..%.4g",
           m.cm.vn, rep.hardEdges, rep.hardVertices, range.first, range.second);
  ctx.log(buf);
  return true;
}

}  // namespace fitmapquad
