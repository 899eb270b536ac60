#pragma once
/// \file fit_io.h
/// File writers for the outputs of FitAndBake (issue 4): 16-bit grey and 8-bit RGB PNGs
/// (libpng), the displacement atlas's JSON sidecar, a real-quad OBJ with per-wedge UVs and an
/// .mtl, a binary PLY with per-vertex quality, and report.json. Each returns "" on success,
/// else the reason (never throws, never prints).
#include <cstdint>
#include <string>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/fit/bake.h"

namespace vcgext {

/// Single-channel 16-bit PNG, row 0 on top. `pix` has width·height values.
std::string WritePngGray16(const std::string& path, int width, int height, const std::vector<std::uint16_t>& pix);
/// 8-bit RGB PNG, row 0 on top. `rgb` has 3·width·height values.
std::string WritePngRgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);
/// Reads back a 16-bit grey PNG (for tests and tools).
std::string ReadPngGray16(const std::string& path, int& width, int& height, std::vector<std::uint16_t>& pix);

/// JSON sidecar of the atlas: image name, size, tile size R, layout (columns, rows, patch f at
/// column f % columns, row f / columns, row 0 on top), the decoding `displacement = offset +
/// scale * value` (absolute units of the mesh), the sampling convention and miss count.
std::string WriteAtlasJson(const std::string& path, const DisplacementAtlas& a, const std::string& pngName,
                           const std::string& normalPngName = "");

/// Wavefront OBJ with real quad faces `f a/ta b/tb c/tc d/td`, one `vt` per wedge (from
/// `wedgeUV`, may be empty: then no vt), `mtllib`/`usemtl` and a `.mtl` next to it whose
/// material has `map_Kd` and `disp` = `texture` (when `texture` is non-empty).
std::string WriteQuadObj(const std::string& path, const QuadData& q,
                         const std::vector<std::array<Eigen::Vector2d, 4>>& wedgeUV, const std::string& texture);

/// Binary little-endian PLY with real quad faces: MeshLab opens it as a quad layer (faux-edge
/// triangle pairs). Debian's MeshLab 2020.09 aborts on every OBJ file (an assertion in vcglib's
/// OBJ importer), so this is the control-mesh format to open in MeshLab; the OBJ is for others.
/// MeshLab splits a polygon along corner 0–2, so each quad is written starting at its free
/// diagonal (FreeDiagonalStarts): the layer MeshLab builds is manifold and pairs back uniquely.
std::string WriteQuadPly(const std::string& path, const QuadData& q);

/// Binary little-endian PLY of a triangle mesh with optional per-vertex `quality` (float).
std::string WritePlyWithQuality(const std::string& path, const TriData& m, const std::vector<double>* quality);

/// report.json: patches, irregular_vertices, degenerate_patches, unprojectable_pct,
/// rms/max limit and displaced errors (permille of the bbox diagonal, per reference vertex),
/// time_s per stage + total, peak_memory_mb, and details (samples, iterations, RMS per
/// iteration, texture size). `extraTimes` are prepended to time_s (e.g. the pipeline's earlier
/// stages) and included in total; `extraMemory` likewise to peak_memory_mb_per_stage.
std::string WriteReportJson(const std::string& path, const FitBakeResult& r,
                            const std::vector<std::pair<std::string, double>>& extraTimes = {},
                            const std::vector<std::pair<std::string, double>>& extraMemory = {});
/// The same JSON as a string.
std::string ReportJson(const FitBakeResult& r, const std::vector<std::pair<std::string, double>>& extraTimes = {},
                       const std::vector<std::pair<std::string, double>>& extraMemory = {});

}  // namespace vcgext
