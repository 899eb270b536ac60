#pragma once
/// \file quad_simplify.h
/// Fitmap-driven quad simplification (Panozzo et al. 2011, §3.2–3.4): turns a triangle mesh M
/// into a coarse, adaptive, pure-quad Catmull-Clark control mesh K whose limit surface follows M.
///
///  1. tri-to-quad on the same vertices (§3.2, tri_to_quad.h), or the caller's quads as they are;
///  2. control points solved so that the limit surface interpolates the input vertices,
///     L V_K = V_M (§3.2, cc_limit.h);
///  3. priority queue of diagonal collapses, cost |d| F_S(phi(c)) (d the diagonal between the
///     limit points of its corners, c the limit point at the patch centre, phi its projection
///     onto M along the limit normal, F_S interpolated barycentrically at the hit); a collapse
///     is feasible only if every patch it enlarges keeps its diameter (max distance centre-corner)
///     within F_M at its centre (§3.3; the paper's sentence states the opposite inequality, its
///     intent is this one); after each collapse immediate doublet removal and edge swaps in the
///     1-ring that strictly lower sum |valence - regular| over the 6 hexagon vertices;
///  4. local fit after each step (§3.4) on W = affected vertices + their 1-ring, twice:
///     tangential smoothing (halfway to the mean of incident face centroids), then re-interpolation
///     of the projections of the limit points onto M (local solve of (1), others frozen);
///  5. a step is undone if it would break manifoldness/topology (QuadMesh operators) or flip a
///     patch against the input (limit normal at the patch centre vs input normal at the hit).
/// Halts when no feasible collapse is left or at `targetPatches`.
#include <string>
#include <vector>

#include <cstring>  // wrap/callback.h uses strcpy without including it
#include <wrap/callback.h>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/quad/tri_to_quad.h"

namespace vcgext {

/// Parameters of SimplifyToQuads. There is no tau here: the M-Fitmap already encodes it.
struct QuadSimplifyParams {
  int targetPatches = 0;          ///< stop at this many patches (0 = only when no feasible collapse is left)
  bool useMFitmap = true;         ///< the projectability test of §3.3 (false: S-cost only, needs targetPatches)
  bool edgeSwaps = true;          ///< valence-improving swaps after each collapse (§3.3.2)
  int fitRounds = 2;              ///< smoothing + re-interpolation rounds per step (paper: 2)
  double smoothingWeight = 0.5;   ///< move this fraction towards the mean of incident centroids (paper: 1/2)
  double solveTolPercent = 1e-5;  ///< interpolation solve tolerance, % of the bbox diagonal (absolute residual)
  int localSolveIterations = 30;  ///< max Gauss-Seidel sweeps of the local solve
  double projectionPercent = 10.0;  ///< max ray length of the projection phi, % of the bbox diagonal
  double boundaryCornerAngleDeg = 45;  ///< remove one-face boundary vertices where the boundary turns less than this (0 = never)
  bool finalReinterpolation = true;  ///< one global solve at the end: all limit vertices back onto the input
  bool validateEveryOperation = false;  ///< test mode: full validity check after every step (O(F) each)
  quad::TriToQuadParams triToQuad;
};

/// Outcome and statistics. `error` non-empty: nothing else is meaningful. `message` carries
/// non-fatal notes (e.g. "too small to simplify").
struct QuadSimplifyResult {
  std::string error;
  std::string message;
  QuadData quads;                 ///< the control mesh K (counter-clockwise quads)
  quad::TriToQuadPath triToQuadPath = quad::TriToQuadPath::Pairing;
  int initialPatches = 0;
  int patches = 0;
  int irregularVertices = 0;
  std::vector<int> valenceHistogram;  ///< index = valence
  int collapses = 0, swaps = 0, doublets = 0;
  int boundaryCorners = 0;        ///< boundary corner removals (open boundaries)
  int rejectedByM = 0;            ///< collapses refused by the M-fitmap test
  int rejectedTopology = 0;       ///< refused by the operators (link condition, boundary, valence)
  int rejectedFlip = 0;           ///< undone because a patch flipped against the input / left it
  int flippedPatches = 0;         ///< final patches whose centre normal disagrees with the input (or miss it)
  int flippedVertices = 0;        ///< final interior vertices whose limit normal disagrees likewise
  double initialSolveResidual = 0;  ///< max |limit - input vertex| after the global solve (absolute)
  int initialSolveIterations = 0;
  double secondsTriToQuad = 0, secondsInitialFit = 0, secondsSimplify = 0, secondsTotal = 0;
};

/// Simplifies triangle mesh `input` into a pure-quad Catmull-Clark control mesh (§3.2–3.4).
/// \param input  manifold, consistently oriented triangle mesh (double arrays)
/// \param scene  Embree scene built on `input` (projection phi)
/// \param S, M   per-input-vertex S-fitmap (1/length) and M-fitmap (absolute radius), as from
///               vcgext::ComputeFitmaps; sizes must equal input.V.size()
/// \param initialQuads  optional: quads on input.V to start from (a layer that is already quads);
///               nullptr = tri-to-quad conversion
/// Errors: empty input, size mismatches, non-finite fitmaps, non-manifold input (reports the
/// number of non-manifold edges and vertices). A mesh too small to simplify returns its pure-quad
/// mesh with `message` set. Cost: roughly O(F log F) collapses, each O(1) local work
/// (a few hundred ray casts and small solves).
QuadSimplifyResult SimplifyToQuads(const TriData& input, const EmbreeScene& scene, const std::vector<double>& S,
                                   const std::vector<double>& M, const QuadSimplifyParams& params,
                                   vcg::CallBackPos* cb = nullptr, const std::vector<Quad>* initialQuads = nullptr);

/// Counts non-manifold edges (more than two faces or inconsistent orientation) and non-manifold
/// vertices (fan not a single disk/half-disk) of a triangle mesh.
void CountNonManifold(const TriData& m, int* nonManifoldEdges, int* nonManifoldVertices);

}  // namespace vcgext
