#pragma once
/// \file far_spikes.h
/// Vertices flung far from the surface: a scanner's wild points ("flying pixels") that the
/// reconstruction kept as the tips of a few needle triangles. One such vertex ten diagonals away
/// makes the bounding box ten times the model's, and everything measured against that box — the
/// Fitmaps' radii, the fit's projection reach, every error the report gives in 1/1000 of its
/// diagonal — becomes the spike's: bunny00 with one vertex 1 000 diagonals away took 117 s for a
/// cage whose RMS error was 5 per mille of the spike's box (the whole bunny under 1 per mille of it),
/// with a warning about "sharp corners or creases". The working copy refuses such a layer with an
/// error that names the spikes and the MeshLab / PyMeshLab filters that remove them.
#include <string>

#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/input_prep.h"

namespace vcgext {

/// A far spike's shortest edge is longer than this many times the mesh's median edge...
inline constexpr double kSpikeEdgeFactor = 100;
/// ... and every triangle at it is a needle: its edge opposite the spike at most this share of
/// the spike's shortest edge (a big flat triangle of a CAD part or a ground plane is not a needle).
inline constexpr double kSpikeNeedleShare = 0.1;
/// The spikes are an error when the bounding box with them has more than this many times the
/// diagonal of the box without them (spikes inside the model's box change little: a warning-free
/// case left to the fit, as the corpus's scan_spikes.off).
inline constexpr double kSpikeBoxFactor = 2;

struct FarSpikes {
  int count = 0;            ///< vertices at the tips of needles kSpikeEdgeFactor x the median edge long
  int first = -1;           ///< the first of them (index into the mesh's V)
  double diag = 0;          ///< the bounding-box diagonal of the vertices in faces
  double diagWithout = 0;   ///< the diagonal of the box of the other vertices (0: none left)
  double edgeFactor = 0;    ///< the longest of their shortest edges, in median edges
  double shortestEdge = 0;  ///< the shortest edge at any of them
};

/// Finds the far spikes of `m` (every vertex in a face): O(F), the median edge from a sample of at
/// most ~100k faces.
FarSpikes FindFarSpikes(const TriData& m);

/// The error for a mesh whose far spikes make its bounding box more than kSpikeBoxFactor times
/// larger than the rest's; empty otherwise. `vertexOf` (optional) maps m's vertices to the
/// layer's indices for the message.
std::string FarSpikesError(const TriData& m, const std::vector<int>* vertexOf = nullptr);

/// What the quad pipeline's filters (Fitmaps, simplification, fit) add to a layer's working copy:
/// its error, if it has none yet, is FarSpikesError's (vertices named as in the layer). The Loop
/// filters take a spiky net as it is: their results are local.
void RefuseFarSpikes(WorkingCopy& w);

/// A layer's working copy for the quad pipeline's filters: PrepareWorkingCopy, then RefuseFarSpikes.
template <class MeshType>
WorkingCopy PrepareQuadPipelineCopy(const MeshType& m) {
  WorkingCopy w = PrepareWorkingCopy(m);
  RefuseFarSpikes(w);
  return w;
}

}  // namespace vcgext
