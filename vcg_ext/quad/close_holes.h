#pragma once
/// \file close_holes.h
/// A scan's small holes closed in the simplification's working copy: the cage is simplified over
/// them as over the surface around, while the fit, the displacement and every reported error still
/// refer to the layer as it is (docs/robustness.md "Many small holes: closed for the layout").
#include <string>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/input_prep.h"

namespace vcgext {

/// What CloseSmallHoles closes.
struct CloseHolesParams {
  /// Holes (boundary loops but their pieces' outlines, kOutlineShare) whose bounding-box diagonal
  /// is below this share (%) of the mesh's bounding-box diagonal are closed: 2 %, under half the
  /// side of an average patch at τ = 1 % on the data set's scans (2.4–4.9 %), far below an opening
  /// a shape has on purpose. 0 = none (maxEdges too).
  double maxDiagonalPercent = 2.0;
  /// ... and those of at most this many straight sides (edges, a run of collinear ones counted
  /// once: a refined copy keeps the count) below maxEdgesDiagonalPercent (a few missing
  /// triangles: on a coarse mesh one triangle can span more than 2 % of the diagonal; the data
  /// set's elephant: 2-4 %). A larger one, however few its edges, is a feature of the shape (the
  /// data set's triangular_hole.off: a 3-edge hole across 45 % of its diagonal).
  int maxEdges = 6;
  double maxEdgesDiagonalPercent = 10.0;
};

/// What was closed.
struct CloseHolesResult {
  /// the input with the closing triangles after its own faces; the same vertices but for the
  /// joined copies (vertexMap)
  TriData mesh;
  int holes = 0;           ///< holes found (outlines excluded)
  int closed = 0;          ///< of which closed
  /// small ones left open because most of their closing (by area) lies on the input, within a
  /// twentieth of the loop's radius: round an island (a piece cut out by cracks, the other sheet
  /// of a doubled wall) or a slit folded over its flap; closing them would double a sheet
  int islands = 0;
  /// small ones left open: their closing would have had a triangle of no area (or vcglib's copy
  /// had no border on the loop)
  int skipped = 0;
  /// small ones left open: their closing would have pinched a vertex or an edge (non-manifold;
  /// ear cutting round a vertex the loop passes several times, where three holes meet)
  int pinched = 0;
  /// Copies of one point on a small hole's loop (the working copy splits a vertex where two holes
  /// touch, to keep the mesh manifold) joined again before closing it: per input vertex its index
  /// in `mesh` (empty when none was joined: the indices are unchanged).
  int joinedVertices = 0;
  std::vector<int> vertexMap;
  double closedAreaPct = 0;  ///< the closing triangles' area, in % of the input's
  /// non-empty: the closings still made the mesh non-manifold after three rounds of leaving the
  /// pinching ones open; nothing was closed (says why)
  std::string refused;
};

/// Closes the small holes of an oriented manifold triangle mesh `m` with vcglib's ear cutting
/// (`tri::Hole::FillHoleEar` with `MinimumWeightEar`, MeshLab's *Close Holes*); no vertex is
/// added or moved, so per-vertex data of `m` (the Fitmaps) hold on the result through
/// vertexMap. The input's faces come first, in order. A closing with a triangle of no area (ear
/// cutting along collinear rim points) is mended by edge flips; one that would make a vertex or
/// an edge non-manifold is left open (`pinched`). Loops are found on the arrays and vcglib is
/// given only the faces round the chosen ones: 0.05 s on a closed 300k-triangle mesh, 0.8 s on
/// one with 5 577 holes, 1.4 s on a 1.2 M-triangle one with 1 297 (the island check's Embree
/// scene of the input included).
CloseHolesResult CloseSmallHoles(const TriData& m, const CloseHolesParams& p = {});

/// CloseSmallHoles on a working copy: its mesh and its vertex maps (liveToMesh, meshToLive) follow.
CloseHolesResult CloseSmallHoles(WorkingCopy& w, const CloseHolesParams& p = {});

}  // namespace vcgext
