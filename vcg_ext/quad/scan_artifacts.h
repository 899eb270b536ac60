#pragma once
/// \file scan_artifacts.h
/// What a raw scan brings that the cage must keep, and the warnings that say what it costs:
/// - debris, small separate pieces (floating specks a scanner or a reconstruction left around the
///   object): every connected piece keeps at least one patch of its own and no collapse merges
///   pieces, so 300 specks around a bunny take 300 of its patches and a budget below that cannot
///   be met;
/// - many small holes: every hole stays a hole of the cage, bordered by patches that cannot grow
///   past it, and a coarse cage's boundary around a one-ring hole opens its limit far wider than
///   the hole (a sphere with 30 such holes at tau = 1 %: 3.3 % of it unreached);
/// - a doubled wall, two sheets of one surface close together and facing the same way (two scans
///   of it left unmerged, a shell copied onto itself): each sheet gets patches of its own and
///   the projections can land on the wrong one;
/// - thin sheets (a plate, a leaf, a scan squashed flat): the paper's halting stops early over
///   the whole sheet, so the count is far above what the shape needs.
/// The filters keep the input as it is (dropping or filling geometry is the user's decision) and
/// name MeshLab's filters that clean it.
#include <string>

#include "vcg_ext/core/embree_scene.h"
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

/// The warning is given from this many holes smaller than the cage's patches on (a CAD part's
/// few bolt holes are not scan damage).
inline constexpr int kManySmallHoles = 10;

/// A boundary loop whose bounding-box diagonal is at least this share of its piece's is the
/// piece's outline, not a hole (FindSmallHoles).
inline constexpr double kOutlineShare = 0.5;

/// Bounding-box diagonal of each vertex's piece (faces joined at shared vertices), by vertex (0
/// for a vertex in no face).
std::vector<double> PieceDiagonals(const TriData& m);

/// A hole of an oriented triangle mesh: a boundary loop that is not its piece's outline
/// (kOutlineShare), as the tails of its half-edges in order, with its bounding-box diagonal;
/// `manifold`: one boundary edge leaves each of its vertices and the loop closes.
struct HoleLoop {
  std::vector<int> vertices;
  double diagonal = 0;
  bool manifold = true;
};
std::vector<HoleLoop> FindHoleLoops(const TriData& m);

/// Holes of an oriented manifold triangle mesh (its boundary loops but the outlines of their
/// pieces, kOutlineShare) and those whose bounding-box diagonal is below `maxDiag`.
struct SmallHoles {
  int holes = 0;
  int small = 0;
};
SmallHoles FindSmallHoles(const TriData& m, double maxDiag);

/// The warning for an input with kManySmallHoles holes or more smaller than the cage's patches
/// (a loop's bbox diagonal below sqrt(input area / patches), the side of an average patch: a
/// patch cannot bend round a smaller hole), with the cage's patches that border a hole; empty
/// otherwise. It names the filter that closes holes (MeshLab and PyMeshLab).
std::string HolesWarning(const TriData& input, const QuadData& cage);

/// A second sheet counts within this share of the bounding-box diagonal ...
inline constexpr double kDoubledWallDistancePercent = 1.0;
/// ... when its normal agrees with the first's to this cosine (a doubled wall), or disagrees to
/// it (cosine below its negative) seen from behind the first (a thin part's other side);
inline constexpr double kDoubledWallCosine = 0.9;
/// and the doubled-wall warning is given when such sheets cover at least this share of the
/// input's area (the data set's 138 OFF files: at most 0.31 %, mannequin-devil; an unmerged copy:
/// 99-100 %);
inline constexpr double kDoubledWallAreaPercent = 5.0;
/// the thin-sheet warning from this share (see ThinSheetWarning).
inline constexpr double kThinSheetAreaPercent = 50.0;
/// Triangles sampled at most (evenly by index): 2 rays each.
inline constexpr long kDoubledWallSamples = 200000;

/// A share of the input's area (sampled triangles, by area) and the median distance to the
/// other sheet over it.
struct SheetShare {
  double areaPercent = 0;
  double medianDistance = 0;
};
/// What a triangle sees along its normal from its centroid, both ways, within
/// kDoubledWallDistancePercent of the diagonal: another triangle facing the same way
/// (kDoubledWallCosine; `doubled`), or, behind it, one facing the other way (the other side of a
/// part thinner than the reach; `thin`). "Behind" is the inside as the input's signed volume
/// says (negative: its faces point inwards; one sign for the whole input).
struct SecondSheets {
  SheetShare doubled;
  SheetShare thin;
  double diagonal = 0;  ///< the input's bounding-box diagonal (what the distances are measured against)
};
SecondSheets FindSecondSheets(const TriData& input, const EmbreeScene& scene);

/// The warning for an input whose doubled wall covers kDoubledWallAreaPercent of its area or more
/// (`s.doubled`), with the cage's patches; empty otherwise. It names the filter that rebuilds
/// one surface from both sheets (MeshLab and PyMeshLab).
std::string DoubledWallWarning(const SecondSheets& s, const QuadData& cage);

/// The warning for a cage simplified by the paper's halting (no patch budget) from an input whose
/// thin part covers kThinSheetAreaPercent of its area or more (`s.thin`): a patch cannot span a
/// rim thinner than itself, so the M-fitmap stops the collapses early over the whole sheet
/// (docs/robustness.md "Thin sheets"); it advises a patch budget. Empty otherwise.
std::string ThinSheetWarning(const SecondSheets& s, const QuadData& cage);

}  // namespace vcgext
