#pragma once
/// \file mesh_io.h
/// Loading and saving vcgext::TMesh (OFF/PLY/OBJ by extension) for tests and tools, through
/// vcglib's importers/exporters (PLY via vcglib's plylib: link `vcg_plylib`).
#include <string>

#include "vcg_ext/core/mesh_types.h"

namespace vcgext {

/// Loads `path` into `m`. Returns an empty string on success, else the reason.
std::string LoadMesh(const std::string& path, TMesh& m);
/// Saves `m` to `path` (format by extension). `withQuality`/`withColor`: per-vertex fields;
/// faux edges (polygonal faces) are written to PLY files as vcg does.
std::string SaveMesh(const std::string& path, TMesh& m, bool withQuality = false, bool withColor = false);

}  // namespace vcgext
