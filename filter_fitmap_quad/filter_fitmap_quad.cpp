#include "filter_fitmap_quad.h"

#include <exception>

#include "filter_table.h"
#include "glue.h"
#include "vcg_ext/core/memory.h"

using namespace fitmapquad;

namespace {

const FilterSpec kFilters[] = {
    {FP_COMPUTE_FITMAPS, "Compute Fitmaps",
     "Computes the Fitmaps of Panozzo et al. 2011 (§3.1) on a triangle mesh: per vertex, the "
     "S-fitmap (how fast the error of a single cubic patch grows with its radius, a^(1/4) of "
     "E(r) = a r^4; unit 1/length) and the M-fitmap (the largest patch radius whose normal "
     "projection onto the mesh stays valid within tolerance tau). Both are stored as per-vertex "
     "attributes (FitmapS, FitmapM) for the quad simplification; the chosen one is copied to "
     "the vertex quality and colour-mapped.",
     MeshFilterInterface::Quality | MeshFilterInterface::Remeshing},
    {FP_QUAD_SIMPLIFICATION, "Fitmap Quad Simplification",
     "Turns the current triangle layer into a NEW layer holding a coarse, adaptive, pure-quad "
     "Catmull-Clark control mesh whose limit surface follows the input (Panozzo et al. 2011, "
     "§3.2-3.4): triangle pairing to quads, control points that make the limit surface "
     "interpolate the input, then a priority queue of diagonal collapses (cost |d| times the "
     "S-fitmap at the patch centre's projection; refused where a patch would outgrow the "
     "M-fitmap), valence-improving edge swaps, doublet removal and local fit + tangential "
     "smoothing after each step. Uses the layer's Fitmaps (computing them if missing). The input "
     "layer is not modified. A layer that is already quads is simplified as quads.",
     MeshFilterInterface::Remeshing | MeshFilterInterface::Polygonal},
    {FP_FIT_AND_BAKE, "Fit Catmull-Clark Surface and Bake Displacement",
     "Fits the Catmull-Clark limit surface of the current pure-quad layer (the control mesh, "
     "e.g. from Fitmap Quad Simplification or any quad remesher) to a reference triangle layer "
     "by sparse least squares on exact limit stencils (Panozzo et al. 2011, §3.5), then bakes "
     "the scalar displacement along the limit normal into a 16-bit PNG atlas (one tile per "
     "patch). New layers: the fitted control mesh (with per-wedge UVs and the displacement "
     "texture), the limit surface (quality = signed distance to the reference) and the "
     "displaced surface. Also writes control.obj (real quads), displacement.png/.json, "
     "optionally normal.png, and report.json (patches, irregular vertices, unprojectable area, "
     "RMS/max errors in 1/1000 of the bbox diagonal, times, peak memory) to the output folder.",
     MeshFilterInterface::Remeshing | MeshFilterInterface::Polygonal | MeshFilterInterface::Texture},
    {FP_LOOP_REFINE, "Loop Surrogate: Refine Surface",
     "Treats the current triangle layer as the control net of a Loop subdivision surface (hard "
     "edges by dihedral angle and/or edge selection, C2 crease curves, fixed corners; Persson "
     "et al.) and meshes its exact limit surface into a new layer: uniform or curvature-adaptive "
     "refinement by centroid insertion and max-min angle edge swaps, every vertex on the limit "
     "surface. Optionally the control net is first made interpolating (the limit surface passes "
     "through the original vertices).",
     MeshFilterInterface::Remeshing},
    {FP_LOOP_SNAP, "Loop Surrogate: Snap Points",
     "Moves every vertex of the current layer to the closest point of the Loop limit surface of "
     "another triangle layer (Newton iteration across control triangles, with a robust "
     "fallback). The distance moved is stored in the vertex quality.",
     MeshFilterInterface::Remeshing | MeshFilterInterface::PointSet},
    {FP_LOOP_CURVATURE, "Loop Surrogate: Curvature",
     "Per-vertex quality = a curvature (mean, Gaussian, max absolute, min or max principal) of "
     "the exact Loop limit surface of the current triangle layer at each vertex's limit point, "
     "colour-mapped.",
     MeshFilterInterface::Quality | MeshFilterInterface::VertexColoring},
};

const FilterSpec* Spec(int id) {
  for (const auto& f : kFilters)
    if (f.id == id) return &f;
  return nullptr;
}

}  // namespace

FilterFitmapQuadPlugin::FilterFitmapQuadPlugin() {
  for (const auto& f : kFilters) {
    typeList << f.id;
    actionList << new QAction(QString(f.name), this);
  }
}

FilterFitmapQuadPlugin::~FilterFitmapQuadPlugin() = default;

QString FilterFitmapQuadPlugin::filterName(FilterIDType id) const {
  const FilterSpec* s = Spec(id);
  return s ? QString(s->name) : QString("unknown filter");
}

QString FilterFitmapQuadPlugin::filterInfo(FilterIDType id) const {
  const FilterSpec* s = Spec(id);
  return s ? QString(s->info) : QString();
}

MeshFilterInterface::FilterClass FilterFitmapQuadPlugin::getClass(QAction* a) {
  const FilterSpec* s = Spec(ID(a));
  return s ? FilterClass(s->classes) : MeshFilterInterface::Remeshing;
}

MeshFilterInterface::FILTER_ARITY FilterFitmapQuadPlugin::filterArity(QAction*) const {
  return SINGLE_MESH;
}

int FilterFitmapQuadPlugin::getPreConditions(QAction*) const { return MeshModel::MM_NONE; }

int FilterFitmapQuadPlugin::postCondition(QAction* a) const {
  switch (ID(a)) {
    case FP_COMPUTE_FITMAPS:
      return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
    case FP_QUAD_SIMPLIFICATION:
    case FP_FIT_AND_BAKE:
    case FP_LOOP_REFINE:
      return MeshModel::MM_NONE;  // the input layers are not modified; new layers are added
    case FP_LOOP_SNAP:
      return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTQUALITY;
    case FP_LOOP_CURVATURE:
      return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
  }
  return MeshModel::MM_ALL;
}

void FilterFitmapQuadPlugin::initParameterSet(QAction* a, MeshDocument& md, RichParameterList& par) {
  switch (ID(a)) {
    case FP_COMPUTE_FITMAPS: InitFitmapsParams(md, par); break;
    case FP_QUAD_SIMPLIFICATION: InitQuadParams(md, par); break;
    case FP_FIT_AND_BAKE: InitFitParams(md, par); break;
    case FP_LOOP_REFINE: InitLoopRefineParams(md, par); break;
    case FP_LOOP_SNAP: InitLoopSnapParams(md, par); break;
    case FP_LOOP_CURVATURE: InitLoopCurvatureParams(md, par); break;
  }
}

bool FilterFitmapQuadPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                         vcg::CallBackPos* cb) {
  if (md.mm() == nullptr) {
    errorMessage = "no current layer";
    Log("Error: no current layer");
    return false;
  }
  GlueContext ctx{md, par, cb, [this](const std::string& s) { Log(s); }, errorMessage};
  vcgext::StagePeakMemoryMb();  // the filter's stages measure their own peak memory from here
  try {
    switch (ID(a)) {
      case FP_COMPUTE_FITMAPS: return ApplyFitmaps(ctx);
      case FP_QUAD_SIMPLIFICATION: return ApplyQuad(ctx);
      case FP_FIT_AND_BAKE: return ApplyFit(ctx);
      case FP_LOOP_REFINE: return ApplyLoopRefine(ctx);
      case FP_LOOP_SNAP: return ApplyLoopSnap(ctx);
      case FP_LOOP_CURVATURE: return ApplyLoopCurvature(ctx);
    }
  } catch (const std::exception& e) {
    return ctx.Fail(std::string("internal error: ") + e.what());
  }
  return ctx.Fail("unknown filter");
}
