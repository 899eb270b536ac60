#pragma once
/// \file filter_table.h
/// The plugin's public API in one place: filter names and parameter names are what `.mlx`
/// scripts and PyMeshLab call, so they never change once released.
#include <QString>

#include <vector>

namespace fitmapquad {

enum FilterId {
  FP_COMPUTE_FITMAPS = 0,
  FP_QUAD_SIMPLIFICATION = 1,
  FP_FIT_AND_BAKE = 2,
  FP_LOOP_REFINE = 3,
  FP_LOOP_SNAP = 4,
  FP_LOOP_CURVATURE = 5,
};

struct FilterSpec {
  FilterId id;
  const char* name;   ///< menu entry and .mlx filter name
  const char* pythonName;  ///< PyMeshLab's function name (2022.02+ plugin: pythonFilterName)
  const char* info;   ///< help text
  int classes;        ///< MeshFilterInterface / FilterPlugin::FilterClass bits
};

/// Every filter, in menu order (filter_specs.cpp), and one by id (null if unknown).
const std::vector<FilterSpec>& AllFilters();
const FilterSpec* Spec(int id);

/// Parameter names (public API), grouped by filter.
namespace param {
// Compute Fitmaps
inline const char* kTau = "tau";                      ///< float, percent
inline const char* kNumRadii = "numRadii";            ///< int
inline const char* kMaxRadiusPerc = "maxRadiusPerc";  ///< float, % of bbox diagonal
inline const char* kChannel = "channel";              ///< enum: 0 = S-fitmap, 1 = M-fitmap
inline const char* kColorize = "colorize";            ///< bool
inline const char* kMode = "mode";                    ///< enum: 0 = fast, 1 = reference
// Fitmap Quad Simplification (also kTau)
inline const char* kTargetPatches = "targetPatches";      ///< int, 0 = until no feasible collapse
inline const char* kUseMFitmap = "useMFitmap";            ///< bool
inline const char* kEqualizedLayout = "equalizedLayout";  ///< bool: the paper's count on an S-fitmap layout
inline const char* kEdgeSwaps = "edgeSwaps";              ///< bool
inline const char* kRegularity = "regularity";            ///< float, QuadSimplifyParams::valenceWeight (0 = off)
inline const char* kSwapSweep = "swapSweep";              ///< int, QuadSimplifyParams::swapSweepChain (0 = off)
inline const char* kSweepTolerance = "sweepTolerance";    ///< float, percent: QuadSimplifyParams::sweepRmsTolerance x 100 (< 0: no guard)
inline const char* kLayoutTrials = "layoutTrials";        ///< int, QuadSimplifyParams::layoutTrials (1 = one pass)
inline const char* kGuard = "thinPartGuard";              ///< float, fraction of F_M (0 = off)
inline const char* kValidate = "validateEveryOperation";  ///< bool (test mode)
inline const char* kWorkingFaces = "workingFaces";        ///< int, triangles of M' (0 = the full input)
inline const char* kFirstWorkingFaces = "firstWorkingFaces";  ///< int, a dense input's first start (0 = none)
inline const char* kCloseHoles = "closeHoles";  ///< float, % of the bbox diagonal: holes closed for the layout (0 = none)
// Fit Catmull-Clark Surface and Bake Displacement
inline const char* kReferenceMesh = "referenceMesh";      ///< mesh (layer position in .mlx)
inline const char* kLimitSegments = "limitSegments";      ///< int, N per patch side
inline const char* kTextureResolution = "textureResolution";  ///< int, R per tile side, 0 = auto
inline const char* kMaxTexels = "maxTexels";  ///< int, cap of the automatic atlas budget, 0 = none
inline const char* kNormalMap = "normalMap";              ///< bool
inline const char* kMaxDistPerc = "maxDistPerc";          ///< float, % of bbox diagonal
inline const char* kFitIterations = "fitIterations";      ///< int
inline const char* kSmoothWeight = "smoothWeight";        ///< float, control-net Laplacian weight (0 = off)
inline const char* kFitDisplacement = "fitDisplacement";  ///< bool, least-squares texels (else point samples)
inline const char* kRendererGrid = "rendererGrid";  ///< bool, bake for a renderer's uniform subdivision (Blender)
inline const char* kAdaptiveTiles = "adaptiveTiles";  ///< bool, automatic R: tile sizes per patch (else one R)
inline const char* kOutputDir = "outputDir";              ///< string, folder for textures/OBJ/report
// Loop Surrogate filters
inline const char* kCreaseAngle = "creaseAngle";          ///< float, degrees (0 = no dihedral test)
inline const char* kUseEdgeSelection = "useEdgeSelection";  ///< bool: selected edges are hard too
inline const char* kRefineMode = "refineMode";            ///< enum: 0 = adaptive, 1 = uniform
inline const char* kInterpolate = "interpolate";          ///< bool
inline const char* kTargetFaces = "targetFaces";          ///< int
inline const char* kSurfaceMesh = "surfaceMesh";          ///< mesh: the control net to snap onto
inline const char* kCurvatureKind = "curvatureKind";      ///< enum: mean, Gaussian, max |k|, min, max
}  // namespace param

}  // namespace fitmapquad
