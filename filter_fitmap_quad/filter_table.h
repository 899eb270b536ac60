#pragma once
/// \file filter_table.h
/// The plugin's public API in one place: filter names and parameter names are what `.mlx`
/// scripts and PyMeshLab call, so they never change once released.
#include <QString>

namespace fitmapquad {

enum FilterId {
  FP_COMPUTE_FITMAPS = 0,
};

struct FilterSpec {
  FilterId id;
  const char* name;   ///< menu entry and .mlx filter name
  const char* info;   ///< help text
  int classes;        ///< MeshFilterInterface::FilterClass bits
};

/// Parameter names (public API), grouped by filter.
namespace param {
// Compute Fitmaps
inline const char* kTau = "tau";                      ///< float, percent
inline const char* kNumRadii = "numRadii";            ///< int
inline const char* kMaxRadiusPerc = "maxRadiusPerc";  ///< float, % of bbox diagonal
inline const char* kChannel = "channel";              ///< enum: 0 = S-fitmap, 1 = M-fitmap
inline const char* kColorize = "colorize";            ///< bool
inline const char* kMode = "mode";                    ///< enum: 0 = fast, 1 = reference
}  // namespace param

}  // namespace fitmapquad
