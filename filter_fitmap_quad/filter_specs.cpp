// The six filters: names, Python names, help texts and classes, shared by the plugin classes of
// both MeshLab interfaces (filter_fitmap_quad.cpp: 2020.09, api2025/: 2022.02+).
#include <iterator>

#include "filter_table.h"
#include "ml_compat.h"

namespace fitmapquad {

namespace {

const FilterSpec kFilters[] = {
    {FP_COMPUTE_FITMAPS, "Compute Fitmaps", "compute_scalar_by_fitmaps_per_vertex",
     "Computes the Fitmaps of Panozzo et al. 2011 (§3.1) on a triangle mesh: per vertex, the "
     "S-fitmap (how fast the error of a single cubic patch grows with its radius, a^(1/4) of "
     "E(r) = a r^4; unit 1/length) and the M-fitmap (the largest patch radius whose normal "
     "projection onto the mesh stays valid within tolerance tau). Both are stored as per-vertex "
     "attributes (FitmapS, FitmapM) for the quad simplification; the chosen one is copied to "
     "the vertex quality and colour-mapped.",
     PluginBase::Quality | PluginBase::Remeshing},
    {FP_QUAD_SIMPLIFICATION, "Fitmap Quad Simplification", "generate_fitmap_quad_simplification",
     "Turns the current triangle layer into a NEW layer holding a coarse, adaptive, pure-quad "
     "Catmull-Clark control mesh whose limit surface follows the input (Panozzo et al. 2011, "
     "§3.2-3.4): triangle pairing to quads, control points that make the limit surface "
     "interpolate the input, then a priority queue of diagonal collapses (cost |d| times the "
     "S-fitmap at the patch centre's projection; refused where a patch would outgrow the "
     "M-fitmap), valence-improving edge swaps, doublet removal and local fit + tangential "
     "smoothing after each step. Uses the layer's Fitmaps (computing them if missing). The input "
     "layer is not modified. A layer that is already quads is simplified as quads.",
     PluginBase::Remeshing | PluginBase::Polygonal},
    {FP_FIT_AND_BAKE, "Fit Catmull-Clark Surface and Bake Displacement", "generate_catmull_clark_fit_and_displacement_bake",
     "Fits the Catmull-Clark limit surface of the current quad layer (the control mesh, "
     "e.g. from Fitmap Quad Simplification or any quad remesher; a quad-dominant layer with "
     "triangles or n-gons is first subdivided once by Catmull-Clark into quads with the same "
     "limit surface) to a reference triangle layer "
     "by sparse least squares on exact limit stencils (Panozzo et al. 2011, §3.5), then bakes "
     "the scalar displacement along the limit normal into a 16-bit PNG atlas (one tile per "
     "patch). New layers: the fitted control mesh (with per-wedge UVs and the displacement "
     "texture), the limit surface (quality = signed distance to the reference) and the "
     "displaced surface. Also writes control.obj (real quads), displacement.png/.json, "
     "optionally normal.png, and report.json (patches, irregular vertices, unprojectable area, "
     "RMS/max errors in 1/1000 of the bbox diagonal, times, peak memory) to the output folder.",
     PluginBase::Remeshing | PluginBase::Polygonal | PluginBase::Texture},
    {FP_LOOP_REFINE, "Loop Surrogate: Refine Surface", "generate_loop_surrogate_refinement",
     "Treats the current triangle layer as the control net of a Loop subdivision surface (hard "
     "edges by dihedral angle and/or edge selection, C2 crease curves, fixed corners; Persson "
     "et al.) and meshes its exact limit surface into a new layer: uniform or curvature-adaptive "
     "refinement by centroid insertion and max-min angle edge swaps, every vertex on the limit "
     "surface. Optionally the control net is first made interpolating (the limit surface passes "
     "through the original vertices).",
     PluginBase::Remeshing},
    {FP_LOOP_SNAP, "Loop Surrogate: Snap Points", "apply_loop_surrogate_snap_points",
     "Moves every vertex of the current layer to the closest point of the Loop limit surface of "
     "another triangle layer (Newton iteration across control triangles, with a robust "
     "fallback). The distance moved is stored in the vertex quality.",
     PluginBase::Remeshing | PluginBase::PointSet},
    {FP_LOOP_CURVATURE, "Loop Surrogate: Curvature", "compute_scalar_by_loop_surrogate_curvature_per_vertex",
     "Per-vertex quality = a curvature (mean, Gaussian, max absolute, min or max principal) of "
     "the exact Loop limit surface of the current triangle layer at each vertex's limit point, "
     "colour-mapped.",
     PluginBase::Quality | PluginBase::VertexColoring},
};

}  // namespace

const std::vector<FilterSpec>& AllFilters() {
  static const std::vector<FilterSpec> all(std::begin(kFilters), std::end(kFilters));
  return all;
}

const FilterSpec* Spec(int id) {
  for (const auto& f : kFilters)
    if (f.id == id) return &f;
  return nullptr;
}

}  // namespace fitmapquad
