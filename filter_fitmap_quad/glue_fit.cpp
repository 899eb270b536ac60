// Glue for "Fit Catmull-Clark Surface and Bake Displacement" (paper §3.5, §4):
// control layer (quads; triangles and n-gons subdivided once) + reference layer -> fitted control, limit, displaced layers,
// displacement/normal textures, quad OBJ and report.json.
#include <algorithm>
#include <cmath>

#include <QDir>
#include <QFileInfo>

#include <Eigen/Geometry>

#include "filter_table.h"
#include "glue.h"
#include "vcg_ext/core/far_spikes.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/pipeline_memory.h"
#include "vcg_ext/core/quad_cleanup.h"
#include "vcg_ext/core/quality.h"
#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/fit_io.h"
#include "vcg_ext/subdiv/subdivide_once.h"

namespace fitmapquad {

void InitFitParams(const MeshDocument& md, RichParameterList& par) {
  const vcgext::FitBakeParams d;
  // Default reference: the first layer that is not the current one (the scan the control mesh
  // was built from comes first in the pipeline).
  const MeshModel* ref = md.mm();
  for (const MeshModel* m : Layers(md))
    if (m != md.mm()) { ref = m; break; }
  par.addParam(MeshParam(param::kReferenceMesh, ref, md, "Reference mesh",
                        "The triangle mesh (scan) the limit surface is fitted to and the "
                        "displacement is measured from."));
  par.addParam(RichInt(param::kLimitSegments, d.limitSegments, "Limit tessellation (N)",
                       "Each patch of the limit surface layer is tessellated N x N."));
  par.addParam(RichInt(param::kTextureResolution, d.textureResolution, "Texture tile size (R)",
                       "Texels per patch side of the displacement atlas, the same for every patch; "
                       "0 = automatic (total samples about the number of reference vertices, as in "
                       "the paper)."));
  par.addParam(RichInt(param::kMaxTexels, d.maxTexels, "Texel budget cap",
                       "With automatic R: at most this many texels in the atlas (the budget is "
                       "otherwise one texel per reference vertex, as in the paper); the default "
                       "4194304 is a 2048 x 2048 texture. 0 = no cap."));
  par.addParam(RichBool(param::kAdaptiveTiles, d.adaptiveTiles, "Tile size per patch",
                        "With automatic R: each patch gets its own tile size (3, 5, 9, 17, 33 or 65 "
                        "texels), so that the texel spacing is about even over the surface (large "
                        "patches get more texels) for the same total samples; tiles stay seamless. "
                        "Off: one R for every patch (the paper's atlas)."));
  par.addParam(RichBool(param::kNormalMap, d.normalMap, "Bake normal map",
                        "Also write an object-space normal map in the same atlas layout."));
  par.addParam(RichBool(param::kFitDisplacement, d.fitDisplacement, "Least-squares displacement",
                        "Texel values fitted so that the displaced surface passes closest to the "
                        "reference vertices (about half the displaced error of the paper's point "
                        "samples at the same texture size). Off: each texel is the distance along "
                        "the limit normal at its point (paper section 4)."));
  par.addParam(RichBool(param::kRendererGrid, d.rendererGrid, "Bake for Blender's subdivision",
                        "Bake the displacement for the surface a renderer rebuilds: the uniform "
                        "subdivision at the level with one vertex per texel of the largest tile, each "
                        "vertex moved along its mesh normal (Blender's Subdivision Surface + Displace "
                        "modifiers; scripts/blender_fitmap.py sets them up). Blender then shows the "
                        "reported displaced error (bunny00: 0.056 instead of 0.083 permille). Off: for "
                        "each patch tessellated at its tile's spacing along the exact limit normal "
                        "(faster on dense scans). See docs/blender.md."));
  par.addParam(RichFloat(param::kMaxDistPerc, float(d.maxDistPercent), "Max distance (% of bbox diagonal)",
                         "Largest projection / displacement distance along the limit normal."));
  par.addParam(RichInt(param::kFitIterations, d.fit.maxIterations, "Fit iterations",
                       "Maximum project -> solve iterations of the least-squares fit."));
  par.addParam(RichFloat(param::kSmoothWeight, float(d.fit.smoothWeight), "Control cage smoothing",
                         "Weight of a control-net Laplacian term in the fit, relative to the mean "
                         "diagonal of the normal equations (0 = off, the paper's fit). Small values "
                         "(0.01-0.1) tame spiky control points on large patches at a small cost in "
                         "limit error."));
  par.addParam(RichString(param::kOutputDir, "", "Output folder",
                          "Where displacement.png (+ .json), normal.png, control.obj (+ .mtl), control.ply and "
                          "report.json are written. Empty: a folder <reference>_cc next to the "
                          "reference mesh file (or in the temporary folder)."));
}

namespace {

// The control mesh as read (quads or polygons), cleaned before it is fitted or subdivided: its
// coordinates as MeshLab 2020.09's float layer holds them (input_prep.h, CoordinatePrecision),
// coincident boundary vertices welded (a cage exported with every face on its own vertices),
// doublets (interior valence-2 vertices, which Catmull-Clark evaluation refuses: foreign quad
// meshes such as MeshLab's triangle pairing and quad-dominant remeshers leave them) merged, as
// the simplification does (§3.3.3). `faces` / `whose` name them in the log. Fails on doublets no
// merge removes (closed pieces of two faces: no Catmull-Clark surface has them).
template <class ControlMesh>
bool CleanControl(GlueContext& ctx, ControlMesh& m, const std::string& faces, const std::string& whose) {
  vcgext::ApplyInputCoordinatePrecision(m.V);
  if (int nw = vcgext::WeldCoincidentVertices(m))
    ctx.log("Fit Catmull-Clark Surface: welded " + std::to_string(nw) +
            " control vertices onto others of the same coordinates (" + faces + " exported each on its own vertices)");
  if (int nd = vcgext::RemoveDoublets(m))
    ctx.log("Fit Catmull-Clark Surface: merged " + std::to_string(nd) + " doublets (interior valence-2 vertices) of " +
            whose);
  int first = -1;
  if (int left = vcgext::CountDoublets(m, &first))
    return ctx.Fail(
        "the control mesh has " + std::to_string(left) +
        " interior vertices of valence 2 that no merge removes (first: vertex " + std::to_string(first) +
        "; merging the two faces round one would repeat a corner: a closed piece of two faces glued along all "
        "their edges, what pairing the triangles of a tetrahedron or an octahedron makes). No Catmull-Clark "
        "surface has such vertices: delete those pieces (Filters > Cleaning and Repairing > Remove Isolated "
        "pieces (wrt Face Num.)), or make the control mesh from the reference with Fitmap Quad Simplification");
  return true;
}

// The control layer's triangles the readers flipped to agree with their neighbours (ImportQuads'
// `flipped`), logged.
void LogFlipped(GlueContext& ctx, int flipped) {
  if (flipped > 0)
    ctx.log("Fit Catmull-Clark Surface: " + std::to_string(flipped) +
            " of the control layer's triangles were stored reversed against their neighbours: read oriented "
            "coherently, each piece as most of its faces (the layer untouched)");
}

// A control layer with triangles or n-gons among its quads (a quad-dominant cage) as quads:
// cleaned (CleanControl) and subdivided once by Catmull-Clark, which keeps its limit surface
// (subdivide_once.h; the result has no doublets to merge).
// Fails with `quadErr` (ImportQuads' error) and why the polygons cannot be read when the layer is
// no polygonal mesh, or has no quad or polygon at all (a triangle mesh is not a Catmull-Clark cage).
bool SubdividedControl(GlueContext& ctx, MeshModel& control, const std::string& quadErr, vcgext::QuadData& quads) {
  vcgext::PolyData poly;
  int flipped = 0;
  const std::string polyErr = vcgext::ImportPolygons(control.cm, poly, &flipped);
  if (!polyErr.empty()) return ctx.Fail(quadErr + "; as polygons: " + polyErr);
  LogFlipped(ctx, flipped);
  int sides[3] = {0, 0, 0};  // triangles, quads, more (as the layer has them)
  for (const auto& f : poly.F) ++sides[std::min<size_t>(f.size(), 5) - 3];
  if (sides[1] + sides[2] == 0)
    return ctx.Fail(quadErr + "; a layer of triangles only is no Catmull-Clark control mesh (Fitmap Quad "
                              "Simplification makes one from it)");
  if (!CleanControl(ctx, poly, "polygons", "the control mesh's polygons")) return false;
  const std::string err = vcgext::SubdivideOnce(poly, quads);
  if (!err.empty()) return ctx.Fail("the control layer cannot be subdivided into quads: " + err);
  ctx.log("Fit Catmull-Clark Surface: the control layer has " + std::to_string(sides[0]) + " triangles and " +
          std::to_string(sides[2]) + " polygons of more than four sides among its " + std::to_string(sides[1]) +
          " quads: subdivided once by Catmull-Clark (the same limit surface) into " + std::to_string(quads.F.size()) +
          " quads, which are the control mesh fitted");
  return true;
}

// The control layer as quads, cleaned (CleanControl); a layer with triangles or n-gons
// subdivided once (SubdividedControl); logs what was paired, welded, merged or subdivided.
bool ReadControlQuads(GlueContext& ctx, MeshModel& control, vcgext::QuadData& quads) {
  int ambiguous = 0, flipped = 0;
  const std::string err = vcgext::ImportQuads(control.cm, quads, &ambiguous, &flipped);
  if (!err.empty()) return SubdividedControl(ctx, control, err, quads);
  LogFlipped(ctx, flipped);
  if (ambiguous > 0)
    ctx.log("Fit Catmull-Clark Surface: " + std::to_string(ambiguous) +
            " quad diagonals were shared by two quads (polygons fanned by an importer); paired by normal agreement");
  return CleanControl(ctx, quads, "quads", "the control mesh");
}

// The reference's working copy (input_prep.h): stray vertices are no surface to fit. Logs its
// repairs and warnings.
bool PrepareReference(GlueContext& ctx, MeshModel& refModel, vcgext::WorkingCopy& w) {
  w = vcgext::PrepareQuadPipelineCopy(refModel.cm);
  if (!w.error.empty()) return ctx.Fail("reference layer: " + w.error);
  for (const auto& n : w.notes) ctx.log("Fit Catmull-Clark Surface: reference layer: " + n);
  for (const auto& n : w.warnings) ctx.log("Warning: Fit Catmull-Clark Surface: reference layer: " + n);
  return true;
}

// The control points in the reference layer's coordinates when the two layers' matrices differ
// (the new layers then carry the reference's matrix, like the files).
bool ControlInReferenceCoordinates(GlueContext& ctx, const MeshModel& control, const MeshModel& refModel,
                                   vcgext::QuadData& quads) {
  Eigen::Matrix4d rel;
  if (!RelativeMatrix(control, refModel, rel))
    return ctx.Fail("the reference layer's transformation matrix cannot be inverted");
  WarnIfNotSimilarity(ctx, refModel, "Fit Catmull-Clark Surface");
  if (rel == Eigen::Matrix4d::Identity()) return true;
  for (auto& v : quads.V) v = (rel * v.homogeneous()).hnormalized();
  ctx.log("Fit Catmull-Clark Surface: the control and reference layers have different transformation matrices: "
          "the control points are fitted in the reference layer's coordinates; the new layers carry its matrix");
  return true;
}

// The filter's parameters as FitBakeParams; fails on a value out of range.
bool ReadFitParams(GlueContext& ctx, vcgext::FitBakeParams& p) {
  p.limitSegments = ctx.par.getInt(param::kLimitSegments);
  p.textureResolution = ctx.par.getInt(param::kTextureResolution);
  p.normalMap = ctx.par.getBool(param::kNormalMap);
  p.fitDisplacement = ctx.par.getBool(param::kFitDisplacement);
  p.adaptiveTiles = ctx.par.getBool(param::kAdaptiveTiles);
  p.rendererGrid = ctx.par.getBool(param::kRendererGrid);
  p.maxTexels = ctx.par.getInt(param::kMaxTexels);
  if (p.maxTexels < 0) return ctx.Fail("the texel budget cap must be 0 (none) or positive");
  p.maxDistPercent = ctx.par.getFloat(param::kMaxDistPerc);
  p.fit.maxIterations = ctx.par.getInt(param::kFitIterations);
  p.fit.smoothWeight = ctx.par.getFloat(param::kSmoothWeight);
  if (p.limitSegments < 1 || p.limitSegments > 64) return ctx.Fail("limit tessellation N must be in [1, 64]");
  if (p.textureResolution < 0 || p.textureResolution > 1024)
    return ctx.Fail("texture tile size R must be 0 (automatic) or in [2, 1024]");
  if (p.textureResolution == 1) return ctx.Fail("texture tile size R must be at least 2");
  if (!(p.maxDistPercent > 0 && p.maxDistPercent <= 100)) return ctx.Fail("max distance must be in (0, 100] percent");
  if (p.fit.maxIterations < 1 || p.fit.maxIterations > 100) return ctx.Fail("fit iterations must be in [1, 100]");
  if (!(p.fit.smoothWeight >= 0 && p.fit.smoothWeight <= 10)) return ctx.Fail("control cage smoothing must be in [0, 10]");
  return true;
}

// The output folder (absolute; empty parameter: <reference>_cc next to the reference mesh
// file, or in the temporary folder), created.
bool MakeOutputDir(GlueContext& ctx, MeshModel& refModel, std::string& dir) {
  QString outDir = ctx.par.getString(param::kOutputDir).trimmed();
  if (outDir.isEmpty()) {
    QFileInfo fi(refModel.fullName());
    outDir = (refModel.fullName().isEmpty() ? QDir::tempPath() : fi.absolutePath()) + "/" +
             (fi.completeBaseName().isEmpty() ? QString("fitmap") : fi.completeBaseName()) + "_cc";
  }
  outDir = QDir(outDir).absolutePath();
  if (!QDir().mkpath(outDir)) return ctx.Fail("cannot create the output folder " + outDir.toStdString());
  dir = outDir.toStdString();
  return true;
}

// The displacement (and normal) textures, their layout and the control mesh as OBJ and PLY.
bool WriteTexturesAndControl(GlueContext& ctx, const std::string& dir, const std::string& png, bool normalMap,
                             const vcgext::FitBakeResult& r) {
  const std::string nrm = normalMap ? dir + "/normal.png" : "";
  for (std::string e : {vcgext::WritePngGray16(png, r.atlas.width, r.atlas.height, r.atlas.q16),
                        normalMap ? vcgext::WritePngRgb8(nrm, r.atlas.width, r.atlas.height, r.atlas.normalRGB)
                                  : std::string(),
                        vcgext::WriteAtlasJson(dir + "/displacement.json", r.atlas, "displacement.png",
                                               normalMap ? "normal.png" : ""),
                        vcgext::WriteQuadObj(dir + "/control.obj", r.fit.control, r.atlas.wedgeUV,
                                             "displacement.png"),
                        vcgext::WriteQuadPly(dir + "/control.ply", r.fit.control)})
    if (!e.empty()) return ctx.Fail(e);
  return true;
}

// The fitted control layer: quads, per-wedge UVs, the displacement texture, and the times and
// memory of the earlier stages followed by this filter's.
MeshModel* AddFittedLayer(GlueContext& ctx, const QString& base, const vcgext::FitBakeResult& r,
                          const std::string& png, StageTimes all, StageMemory memory, const Matrix44m& tr) {
  MeshModel* fitted = ctx.md.addNewMesh("", base + " fitted", false);
  fitted->cm.Tr = tr;
  fitted->updateDataMask(MeshModel::MM_WEDGTEXCOORD | MeshModel::MM_POLYGONAL);
  vcgext::ExportQuads(r.fit.control, fitted->cm, &r.atlas.wedgeUV);
  AddTexture(*fitted, png);
  UpdateBoxAndNormals(*fitted);
  for (const auto& t : r.times) all.push_back(t);
  SetStageTimes(fitted->cm, all);
  for (const auto& m : r.memory) memory.push_back(m);
  SetStageMemory(fitted->cm, memory);
  return fitted;
}

// A tessellated surface as a layer, quality coloured over [-range, range]; the first surface
// (range 0) sets range from its 1-99 % quality percentiles.
void AddSurfaceLayer(GlueContext& ctx, const vcgext::LimitTessellation& t, const QString& name,
                     const Matrix44m& tr, double& range) {
  MeshModel* m = ctx.md.addNewMesh("", name, false);
  m->cm.Tr = tr;
  m->updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
  vcgext::ExportTriangles(t.mesh, m->cm, t.quality.empty() ? nullptr : &t.quality);
  if (range == 0) {
    const auto pr = vcgext::QualityPercentiles(m->cm, 1.0, 99.0);
    range = std::max({std::abs(pr.first), std::abs(pr.second), 1e-12});
  }
  vcgext::ColorizeQualityRange(m->cm, -range, range);
  UpdateBoxAndNormals(*m);
}

// Both surfaces are coloured over one symmetric range (the limit layer's 1-99 % percentiles), so
// their colours compare: green = on the reference, red / blue = below / above it.
void AddSurfaceLayers(GlueContext& ctx, const QString& base, const vcgext::FitBakeResult& r,
                      const Matrix44m& tr) {
  double range = 0;
  AddSurfaceLayer(ctx, r.limit, base + " limit", tr, range);
  AddSurfaceLayer(ctx, r.displaced, base + " displaced", tr, range);
  ctx.log("Fit Catmull-Clark Surface: limit and displaced layers coloured by signed distance to the reference over [" +
          std::to_string(-range) + ", " + std::to_string(range) + "] (red below, blue above)");
}

// The report and warnings in the log, the figures returned to the caller, the files written.
void ReportFit(GlueContext& ctx, const vcgext::FitBakeResult& r, bool normalMap, const std::string& dir) {
  ctx.log(vcgext::FormatReport(r));
  for (const auto& w : r.warnings) ctx.log("Warning: Fit Catmull-Clark Surface: " + w);
  ctx.Value("patches", r.fit.patches);
  ctx.Value("irregular_vertices", r.fit.irregularVertices);
  ctx.Value("rms_limit_permille", r.metrics.rmsLimitPermille);
  ctx.Value("max_limit_permille", r.metrics.maxLimitPermille);
  ctx.Value("rms_displaced_permille", r.metrics.rmsDisplacedPermille);
  ctx.Value("max_displaced_permille", r.metrics.maxDisplacedPermille);
  ctx.Value("unprojectable_pct", r.metrics.unprojectablePct);
  ctx.Value("warnings", double(r.warnings.size()));
  ctx.log("Fit Catmull-Clark Surface: wrote displacement.png, displacement.json, " +
          std::string(normalMap ? "normal.png, " : "") + "control.obj (+ .mtl), control.ply, report.json to " + dir);
}

}  // namespace

bool ApplyFit(GlueContext& ctx) {
  MeshModel& control = *ctx.md.mm();
  MeshModel* refModel = GetMeshParam(ctx.md, ctx.par, param::kReferenceMesh);
  if (!refModel) return ctx.Fail("the reference layer is missing");
  if (refModel == &control)
    return ctx.Fail("the reference layer must be another layer than the control mesh (the current layer)");
  vcgext::FitBakeParams p;
  if (!ReadFitParams(ctx, p)) return false;
  const std::string memErr =
      vcgext::CheckPipelineMemory(vcgext::PipelineStep::FitAndBake, refModel->cm.fn, p.fit.maxMemoryMb);
  if (!memErr.empty()) return ctx.Fail("Fit Catmull-Clark Surface: " + memErr);
  vcgext::QuadData quads;
  if (!ReadControlQuads(ctx, control, quads)) return false;
  vcgext::WorkingCopy w;
  if (!PrepareReference(ctx, *refModel, w)) return false;
  if (!ControlInReferenceCoordinates(ctx, control, *refModel, quads)) return false;
  const vcgext::TriData& ref = w.mesh;
  std::string dir;
  if (!MakeOutputDir(ctx, *refModel, dir)) return false;

  vcgext::EmbreeScene scene(ref);
  if (!scene.Ok()) return ctx.Fail(scene.Error());
  vcgext::FitBakeResult r = vcgext::FitAndBake(quads, ref, scene, p, ctx.cb);
  if (!r.error.empty()) return ctx.Fail("Fit Catmull-Clark Surface: " + r.error);

  // Files first: a layer's texture must exist when MeshLab shows it.
  const std::string png = dir + "/displacement.png";
  if (!WriteTexturesAndControl(ctx, dir, png, p.normalMap, r)) return false;
  StageTimes earlier = GetStageTimes(control.cm);
  StageMemory earlierMemory = GetStageMemory(control.cm);
  const std::string err = vcgext::WriteReportJson(dir + "/report.json", r, earlier, earlierMemory);
  if (!err.empty()) return ctx.Fail(err);

  // Layers: fitted control (quads, per-wedge UVs, displacement texture), limit, displaced.
  const QString base = control.label();
  const Matrix44m tr = refModel->cm.Tr;
  MeshModel* fitted = AddFittedLayer(ctx, base, r, png, earlier, earlierMemory, tr);
  AddSurfaceLayers(ctx, base, r, tr);
  ctx.md.setCurrentMesh(fitted->id());
  ReportFit(ctx, r, p.normalMap, dir);
  return true;
}

}  // namespace fitmapquad
