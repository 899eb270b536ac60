#pragma once
/// \file staircase.h
/// Staircase surfaces: a scan whose coordinates were rounded to a coarse step (written with two
/// significant digits) or a surface of axis-aligned voxel faces (a segmentation mask or an
/// occupancy grid exported as it is). The Fitmaps take every step for detail, so the cage follows
/// the steps: bunny00 at two digits 31 292 patches for its 381, bunny00 voxelized at 80 voxels
/// across 11 834, elephant at 60 voxels 5 034 for its 499.
///
/// Decision (docs/robustness.md "Rounded coordinates and voxel faces"): warn with the cause and the
/// fix, do not smooth (the lost digits cannot be recovered, and smoothing is the user's call: the
/// displacement then restores the smoothed surface, not the staircase). MeshLab's Taubin Smooth at
/// its defaults brings those three to 472, 349 and 680 patches.
#include <string>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// What FindStaircase measured.
struct Staircase {
  bool rounded = false;  ///< coordinates rounded: corners met and the step is coarse
  bool voxels = false;   ///< axis-aligned faces in steps (a voxel export)
  int coincidentFaces = 0;      ///< triangles with two corners at one position (distinct vertices)
  int faces = 0;                ///< triangles of the layer
  double step = 0;              ///< the coordinates' step (0 when not measured)
  double medianEdge = 0;
  double axisAlignedShare = 0;  ///< area share of the triangles facing along an axis (0..1)
  double stepEdgeShare = 0;     ///< share of the edges between two triangles at 60° or more (0..1)
  double diagonal = 0;
  /// The step in median edges when warned about, else 0.
  double StepEdges() const { return (rounded || voxels) && medianEdge > 0 ? step / medianEdge : 0; }
};

/// `raw`: the layer's triangles as read (coincident corners are counted there); `mesh`: its
/// working copy (merged, manifold, oriented: its edges between two triangles are the steps').
/// Rounded: at least 10 triangles, and 0.5 % of them, have two corners at one position and the
/// coordinates' step is at least a quarter of the median edge. Voxels: 90 % of the area faces
/// along an axis, every axis has 10 coordinate values or more, the step is at least a quarter of
/// the median edge, and 20 % of the edges between two triangles turn by 60° or more. The
/// coordinates' step: per axis, the median over vertices of the gap to the nearest other value on
/// that axis; the smallest over the axes. Costs two passes over the triangles unless a first test
/// passes (the step sorts the coordinates, the steps' share the edges).
Staircase FindStaircase(const TriData& raw, const TriData& mesh);

/// The warning for `s` ("" when neither kind was found).
std::string StaircaseWarning(const Staircase& s);

}  // namespace vcgext
