#pragma once
/// \file decimate.h
/// The working resolution M' of a dense input (Fitmaps paper §4, "large meshes": the control mesh
/// is initialised on a decimated M' while all fitting and mapping refer to the full M):
/// vcglib's quadric edge collapse (the decimator behind MeshLab's "Simplification: Quadric Edge
/// Collapse Decimation"), with topology and boundary preserved, on a copy of the mesh.
#include <string>
#include <vector>

#include <cstring>  // wrap/callback.h uses strcpy without including it
#include <wrap/callback.h>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// The rule that chooses the working size (docs/multires.md): an input with more than
/// `maxFaces` triangles is decimated to `maxFaces`; smaller inputs are used as they are.
struct WorkingResolutionParams {
  int maxFaces = 0;              ///< 0 = always the full input
  /// A smaller input is refined by edge midpoints (the same surface) until it has at least this
  /// many triangles: a cube of 12 triangles would otherwise start from 6 quads, whose smooth
  /// limit stays far inside the cube (0 = never).
  int minFaces = 0;
  /// A start mesh with a vertex of higher valence (a cone's apex, the poles of a UV sphere) is
  /// remeshed isotropically (vcglib's IsotropicRemeshing, about as many triangles, projected
  /// onto the input): a valence-500 vertex makes every collapse, stencil and fit around it cost
  /// hundreds of times more (0 = never).
  int maxValence = 0;
  bool preserveBoundary = true;  ///< boundary vertices are not collapsed (open scans keep their rim)
  /// From this many input triangles (and a target at most half of them) the decimation runs on
  /// two threads, one per half of the mesh, then one pass over the whole (DecimateSplit in
  /// decimate.cpp; the same topology guarantees). Below it one thread is fast enough (bunny00's
  /// 150k triangles: 1.5 s). 0 = always one thread.
  int splitMinFaces = 200000;
  /// Evaluate each candidate collapse with vcglib's own TriEdgeCollapseQuadric::ComputePriority
  /// instead of the one-pass evaluation (decimate.cpp, DCollapseT): the same values, slower; the
  /// reference the tests compare against.
  bool vcgPriority = false;
};

struct DecimateResult {
  TriData mesh;        ///< the decimated mesh (or a copy of the input when it is small enough)
  bool decimated = false;
  int refinements = 0;  ///< midpoint refinements applied to a small input (minFaces)
  int remeshedValence = 0;  ///< the highest valence that made the input be remeshed (maxValence), else 0
  /// that valence when the remesh was not manifold (vcglib's isotropic remeshing across the narrow
  /// gaps of a cracked scan): `mesh` is then empty (no start mesh), else 0
  int remeshRefusedValence = 0;
  bool reused = false;             ///< the same request as the previous one in this process: its result, not recomputed
  bool skippedDegenerate = false;  ///< not decimated: zero-area faces that edge flips could not remove
  /// Edge flips that removed zero-area faces from the copy before its decimation (vcglib's quadrics
  /// are NaN on them): a corner on the opposite edge, as float rounding leaves in thin triangles
  /// of scans and of midpoint-refined meshes. 0 when the input had none.
  int zeroAreaFlips = 0;
  bool split = false;              ///< decimated in two halves on two threads (splitMinFaces)
  double seconds = 0;
};

/// M' of `m` by the rule above (decimated above maxFaces, refined below minFaces, remeshed above
/// maxValence). Zero-area faces in an input to decimate are first flipped away on the copy
/// (vcglib's RemoveTVertexByFlip); where a zero-area face is left (coincident corners) the input
/// is used at full resolution (`skippedDegenerate`). Preconditions: manifold, oriented (a WorkingCopy). The result
/// keeps the genus, components and boundary loops (vcglib's PreserveTopology / boundary
/// options); it may stop above the target where no valid collapse is left. Cost O(F log F).
/// The three latest results are kept (small meshes) and returned again for the same mesh and
/// parameters (exact fingerprint of the arrays): the Fitmaps and the simplification of one
/// pipeline share one decimation. Thread-safe.
DecimateResult WorkingResolution(const TriData& m, const WorkingResolutionParams& p,
                                 vcg::CallBackPos* cb = nullptr);

/// Where the quad simplification starts (paper §4; docs/multires.md, docs/robustness.md).
struct StartMeshParams {
  int workingFaces = 40000;           ///< M' size: larger inputs are decimated to it (0 = never)
  /// The Fitmaps' working size: M' is decimated from the Fitmaps' M'_F, so the decimation that
  /// "Compute Fitmaps" made of the layer is reused (WorkingResolution keeps recent results).
  int fitmapsWorkingFaces = 100000;
  int minFaces = 1000;                ///< smaller inputs start from their midpoint refinement
  int maxValence = 24;                ///< a vertex of higher valence: start from an isotropic remesh
};
struct StartMesh {
  DecimateResult work;                ///< the start mesh (work.mesh) and what was done to get it
  bool differs = false;               ///< false: start from the input itself
  std::vector<std::string> notes;     ///< log lines (what was done, at which size, how long)
  std::vector<std::string> warnings;  ///< log warnings
  std::string error;                  ///< non-empty: there is no start mesh (says why and what to do)
};
/// The start mesh of the quad simplification of `input` (a WorkingCopy's mesh): WorkingResolution
/// through M'_F, then to workingFaces, refined below minFaces, remeshed above maxValence. All zero
/// parameters (a pure-quad layer simplified from its quads): the input itself.
StartMesh ChooseStartMesh(const TriData& input, const StartMeshParams& p, vcg::CallBackPos* cb = nullptr);

}  // namespace vcgext
