#pragma once
/// \file input_prep.h
/// The private working copy every filter runs on (issue 16: "every input a user can load"):
/// the layer's triangles cleaned so that the algorithms see a manifold, consistently oriented
/// mesh without stray elements, with a map back to the layer's vertices for per-vertex results.
/// The layer itself is never modified.
///
/// Steps, in order (each counted, and named in `notes` when it changed something):
///  1. exact duplicate vertices (bitwise-equal coordinates, what STL soups and unwelded exports
///     hold) are merged — unless merging is what makes the surface non-manifold (coincident
///     vertices kept apart on purpose: a surface touching itself, the sides of a crack); a soup
///     whose copies of a vertex were rounded face by face is welded within 1e-6 of the diagonal;
///  2. faces that repeat a vertex after merging (degenerate) and repeated faces (same three
///     vertices, either orientation) are dropped; seams between separately meshed parts
///     (seams.h) are closed: boundary vertices within 1e-6 of the diagonal of another boundary's
///     are welded, and a vertex on another face's boundary edge (a T-junction) splits that face;
///     boundary vertices left within a tenth of the boundary's median edge of another boundary's
///     (cracks wider than that weld) are counted and warned about, not welded;
///  3. on edges of three or more triangles, the two that continue each other keep the edge and
///     the others are separated (a fin comes off); vertices where separate sheets touch (a
///     bow-tie) are split into one copy per sheet, as MeshLab's Repair non Manifold Vertices does;
///  4. each connected component is oriented coherently, keeping the orientation of the majority
///     of its faces; a non-orientable component (a Möbius strip) is an error;
///  5. unreferenced vertices are left out (they get no value: -1 in `liveToMesh`).
/// A warning names the precision loss when coordinates are far from the origin relative to the
/// model's size (MeshLab 2020.09 stores single-precision floats).
///
/// Decision (docs/robustness.md): these steps run on index arrays rather than through vcglib's
/// tri::Clean on a copy of the layer, because the filters must write per-vertex results back to
/// the layer's own vertices, and tri::Clean's merges and compactions do not report which vertex
/// went where. Every step but the soup weld and the T-junctions is exact (no tolerance); each is
/// tested against hand-made cases.
#include <string>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

struct WorkingCopy {
  std::string error;                  ///< non-empty: the input cannot be used (says why)
  TriData mesh;                       ///< referenced vertices only, manifold, oriented
  std::vector<int> liveToMesh;        ///< per live layer vertex: its vertex in `mesh`, or -1
  std::vector<int> meshToLive;        ///< per mesh vertex: one live layer vertex mapped to it
  int mergedVertices = 0;             ///< duplicates merged into another vertex
  int weldedVertices = 0;             ///< of a triangle soup, merged within 1e-6 of the diagonal
  int seamVertices = 0;               ///< boundary vertices welded to another boundary's (seams.h)
  int closedTJunctions = 0;           ///< vertices on another face's boundary edge, split into it
  int crackVertices = 0;              ///< boundary vertices left near another boundary's (warned, not welded)
  double staircaseStepEdges = 0;      ///< coordinates' step in median edges when warned as a staircase, else 0
  int unreferencedVertices = 0;       ///< live vertices in no face (after dropping faces)
  int degenerateFaces = 0;            ///< faces repeating a vertex (in the layer or after merging)
  int duplicateFaces = 0;             ///< repeated faces dropped
  int flippedFaces = 0;               ///< faces re-oriented
  int components = 0;
  int nonManifoldEdges = 0, nonManifoldVertices = 0, nonOrientableComponents = 0;
  /// non-manifold vertices split into one copy per sheet (the copies follow the layer's vertices
  /// in `mesh`; each maps to its layer vertex in meshToLive, the layer vertex to the first sheet's)
  int splitVertices = 0;
  /// edges of three or more triangles whose triangles were separated (the split copies their
  /// vertices for a triangle that does not continue the surface across the edge: a fin comes off)
  int separatedEdges = 0;
  std::vector<std::string> notes;     ///< what was repaired, one line each (for the log)
  std::vector<std::string> warnings;  ///< what the user should know (precision)
};

/// Builds the working copy from `raw` (the layer's live vertices in order and its faces, as
/// ImportTriangles gives them; faces may repeat vertices). Cost O(F log F). The latest result
/// for a mesh of 200k triangles or more is kept and returned again for the same arrays (the
/// pipeline's three filters prepare the same layer). Thread-safe.
WorkingCopy PrepareWorkingCopy(const TriData& raw);

/// Per-live-vertex values from per-mesh-vertex ones (`fill` where a vertex has none).
template <class T>
std::vector<T> ToLiveVertices(const WorkingCopy& w, const std::vector<T>& perMeshVertex, T fill) {
  std::vector<T> out(w.liveToMesh.size(), fill);
  for (size_t i = 0; i < out.size(); ++i)
    if (w.liveToMesh[i] >= 0) out[i] = perMeshVertex[w.liveToMesh[i]];
  return out;
}

/// Values of a per-vertex attribute of the layer `m` (read on its live vertices, in order) for
/// the working copy's vertices (each takes the value of its meshToLive vertex).
template <class MeshType, class Handle>
std::vector<double> AttributeOnWorkingCopy(const WorkingCopy& w, const MeshType& m, Handle h) {
  std::vector<double> live;
  for (const auto& v : m.vert)
    if (!v.IsD()) live.push_back(double(h[v]));
  std::vector<double> out;
  out.reserve(w.meshToLive.size());
  for (int i : w.meshToLive) out.push_back(live[size_t(i)]);
  return out;
}

/// Re-indexes quads given on the layer's live vertices (a polygonal layer's quads) onto the
/// working copy. False (quads unusable: use the working copy's triangles) if a corner has no
/// working vertex, a quad repeats a vertex after merging, a quad side runs as no working triangle's
/// side does (a quad the working copy dropped, or one oriented against the face the working copy
/// made of it: read the quads oriented, ImportQuads' `flipped`), faces were split at T-junctions,
/// or vertices split.
bool RemapQuadsToWorkingCopy(const WorkingCopy& w, std::vector<Quad>& quads);

/// Precision of the coordinates PrepareWorkingCopy reads from a layer. MeshLab 2020.09 stores a
/// layer's coordinates as float, MeshLab 2022.02+ (PyMeshLab) as double, so the same file gives
/// the two plugins numbers that differ in the 8th digit, and the simplification's greedy choices
/// (the quadric decimation of the working resolution first of all) amplify that into different
/// cages (bunny00: 394 vs 394 patches but 110 vs 119 irregular vertices, RMS limit 0.85 vs
/// 0.97 per mille). `Float` (what the 2022.02+ plugin sets when it loads) rounds each coordinate
/// to float, as MeshLab 2020.09's readers do, so both plugins compute on the same numbers; a layer
/// for which float is too coarse (a coordinate's float spacing, 2^-24 |x|, above 1e-6 of the bbox
/// diagonal: a small object far from the origin, e.g. georeferenced) keeps double.
/// Process-wide; `AsGiven` (the default) leaves the values alone. docs/meshlab2025_feasibility.md.
enum class CoordinatePrecision { AsGiven, Float };
void SetInputCoordinatePrecision(CoordinatePrecision p);
CoordinatePrecision InputCoordinatePrecision();

/// Rounds the coordinates `V` to float if that moves none by more than 2^-24 |x| <= 1e-6 of the
/// bbox diagonal (see CoordinatePrecision); returns whether it did.
bool RoundCoordinatesToFloat(std::vector<Vec3>& V);
/// RoundCoordinatesToFloat under CoordinatePrecision::Float, nothing under AsGiven: what every
/// reader of a layer's coordinates (the working copy, the fit's control layer) applies.
void ApplyInputCoordinatePrecision(std::vector<Vec3>& V);

/// Reads a vcg layer (polygonal layers as their triangles: faux edges are only flags) and
/// prepares its working copy (coordinates as ApplyInputCoordinatePrecision leaves them). Errors
/// of ImportTriangles (empty, point cloud, NaN/Inf, face indices out of range) come through
/// `error`.
template <class MeshType>
WorkingCopy PrepareWorkingCopy(const MeshType& m) {
  TriData raw;
  ImportReport rep = ImportTriangles(m, raw, /*allowPolygonal=*/true, /*keepDegenerate=*/true);
  if (!rep.error.empty()) {
    WorkingCopy w;
    w.error = rep.error;
    return w;
  }
  ApplyInputCoordinatePrecision(raw.V);
  return PrepareWorkingCopy(raw);
}

}  // namespace vcgext
