#pragma once
/// \file debris.h
/// Small separate pieces of a cage: scan debris (floating specks a scanner or a reconstruction
/// left around the object). Every connected piece of the input keeps at least one patch of its
/// own, and no collapse can merge pieces, so 300 specks around a bunny take 300 of its patches
/// and a budget below that cannot be met. The filters keep every piece (dropping geometry is the
/// user's decision) and say what the specks cost, naming MeshLab's filter that removes them.
#include <string>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// A piece counts as small below this share of the input's bounding-box diagonal (its own bbox
/// diagonal, what MeshLab's Remove Isolated pieces (wrt Diameter) measures).
inline constexpr double kDebrisDiagPercent = 2.0;
/// ... and the warning is given when the small pieces hold at least this share of the patches.
inline constexpr double kDebrisPatchSharePercent = 2.0;

/// Connected pieces of a cage (quads joined through shared vertices) and those whose bounding-box
/// diagonal is below `maxDiag`, with their patches.
struct SmallPieces {
  int pieces = 0;
  int small = 0;
  long smallPatches = 0;
};
SmallPieces FindSmallPieces(const QuadData& cage, double maxDiag);

/// The warning for a cage whose small pieces (kDebrisDiagPercent of `inputDiag`) hold at least
/// kDebrisPatchSharePercent of its patches; empty otherwise. It gives the counts and names the
/// filter that removes such pieces (MeshLab and PyMeshLab) with the diameter to give it.
std::string DebrisWarning(const QuadData& cage, double inputDiag);

}  // namespace vcgext
