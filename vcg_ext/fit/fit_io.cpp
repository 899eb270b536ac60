#include "vcg_ext/fit/fit_io.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>

namespace vcgext {

namespace {
struct FileCloser {
  void operator()(FILE* f) const { if (f) std::fclose(f); }
};

std::string WritePng(const std::string& path, int w, int h, int colorType, int bitDepth, int channels,
                     const unsigned char* rows, size_t rowBytes) {
  if (w <= 0 || h <= 0) return "empty image";
  std::unique_ptr<FILE, FileCloser> fp(std::fopen(path.c_str(), "wb"));
  if (!fp) return "cannot open " + path + " for writing: " + std::strerror(errno);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return "libpng: cannot create the write struct";
  png_infop info = png_create_info_struct(png);
  if (!info) { png_destroy_write_struct(&png, nullptr); return "libpng: cannot create the info struct"; }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return "libpng failed writing " + path;
  }
  png_init_io(png, fp.get());
  png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), bitDepth, colorType, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bitDepth == 16) png_set_swap(png);  // our samples are host (little-endian) order
  (void)channels;
  for (int y = 0; y < h; ++y) png_write_row(png, const_cast<png_bytep>(rows + size_t(y) * rowBytes));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return {};
}

std::string Esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') { o += '\\'; o += c; }
    else if (static_cast<unsigned char>(c) < 0x20) { char b[8]; std::snprintf(b, sizeof b, "\\u%04x", c); o += b; }
    else o += c;
  }
  return o;
}

std::string Num(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream o;
  o << std::setprecision(10) << v;
  return o.str();
}

std::string BaseName(const std::string& p) {
  size_t s = p.find_last_of('/');
  return s == std::string::npos ? p : p.substr(s + 1);
}

}  // namespace

std::string WritePngGray16(const std::string& path, int width, int height, const std::vector<std::uint16_t>& pix) {
  if (pix.size() != size_t(width) * height) return "image size mismatch";
  return WritePng(path, width, height, PNG_COLOR_TYPE_GRAY, 16, 1, reinterpret_cast<const unsigned char*>(pix.data()),
                  size_t(width) * 2);
}

std::string WritePngRgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (rgb.size() != size_t(width) * height * 3) return "image size mismatch";
  return WritePng(path, width, height, PNG_COLOR_TYPE_RGB, 8, 3, rgb.data(), size_t(width) * 3);
}

std::string ReadPngGray16(const std::string& path, int& width, int& height, std::vector<std::uint16_t>& pix) {
  std::unique_ptr<FILE, FileCloser> fp(std::fopen(path.c_str(), "rb"));
  if (!fp) return "cannot open " + path;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return "libpng: cannot create the read struct";
  png_infop info = png_create_info_struct(png);
  if (!info) { png_destroy_read_struct(&png, nullptr, nullptr); return "libpng: no info struct"; }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return "libpng failed reading " + path;
  }
  png_init_io(png, fp.get());
  png_read_info(png, info);
  width = int(png_get_image_width(png, info));
  height = int(png_get_image_height(png, info));
  if (png_get_bit_depth(png, info) != 16 || png_get_color_type(png, info) != PNG_COLOR_TYPE_GRAY) {
    png_destroy_read_struct(&png, &info, nullptr);
    return "not a 16-bit grey PNG";
  }
  png_set_swap(png);
  pix.resize(size_t(width) * height);
  for (int y = 0; y < height; ++y) png_read_row(png, reinterpret_cast<png_bytep>(pix.data() + size_t(y) * width), nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return {};
}

std::string WriteAtlasJson(const std::string& path, const DisplacementAtlas& a, const std::string& pngName,
                           const std::string& normalPngName) {
  std::ofstream o(path);
  if (!o) return "cannot open " + path + " for writing";
  o << "{\n"
    << "  \"image\": \"" << Esc(pngName) << "\",\n"
    << "  \"normal_image\": " << (normalPngName.empty() ? "null" : "\"" + Esc(normalPngName) + "\"") << ",\n"
    << "  \"width\": " << a.width << ",\n  \"height\": " << a.height << ",\n"
    << "  \"tile_sizes\": \"" << (a.adaptive ? "adaptive" : "uniform") << "\",\n"
    << "  \"tile\": " << a.R << ",\n";
  if (!a.adaptive) o << "  \"columns\": " << a.cols << ",\n  \"rows\": " << a.rows << ",\n";
  o << "  \"patches\": " << a.wedgeUV.size() << ",\n"
    << "  \"samples\": " << a.Samples() << ",\n"
    << "  \"scale\": " << Num(a.scale) << ",\n  \"offset\": " << Num(a.offset) << ",\n"
    << "  \"decode\": \"displacement = offset + scale * value (mesh units, along the unit "
    << (a.rendererLevel > 0 ? "vertex normal of the uniform level-" + std::to_string(a.rendererLevel) +
                                  " subdivision (corner-angle-weighted quad normals, as Blender's), "
                                  "sampled at that subdivision's vertices)"
                            : std::string("limit normal)"))
    << "\",\n"
    << "  \"baked_for\": \"" << (a.rendererLevel > 0 ? "renderer" : "limit") << "\",\n"
    << "  \"subdivision_level\": " << a.rendererLevel << ",\n"
    << "  \"layout\": \""
    << (a.adaptive ? "patch f -> tiles[f] = [x, y, size]: the size x size texels whose top-left pixel is (x, y) "
                     "(row 0 at the top of the image); sizes are 2^k+1, and along an edge shared with a "
                     "coarser tile the extra texels interpolate the coarser tile's (seamless); "
                   : "patch f -> tile column f % columns, row f / columns (row 0 at the top of the image), "
                     "tile x tile texels; ")
    << "texel (i,j) of a tile = limit parameter (u,v) = (i/(size-1), j/(size-1)), j growing downwards; "
       "wedge UVs sit at the corner texel centres (v up)\",\n";
  if (a.adaptive) {
    o << "  \"tiles\": [";
    for (int f = 0; f < a.Patches(); ++f)
      o << (f ? ", " : "") << "[" << a.tileX[f] << ", " << a.tileY[f] << ", " << a.tileR[f] << "]";
    o << "],\n";
  }
  o << "  \"misses\": " << a.misses << "\n}\n";
  return o ? "" : "write error on " + path;
}

std::string WriteQuadObj(const std::string& path, const QuadData& q,
                         const std::vector<std::array<Eigen::Vector2d, 4>>& wedgeUV, const std::string& texture) {
  const bool uv = !wedgeUV.empty();
  if (uv && wedgeUV.size() != q.F.size()) return "wedge UVs do not match the faces";
  std::string mtl = path;
  size_t dot = mtl.find_last_of('.');
  if (dot != std::string::npos && mtl.find('/', dot) == std::string::npos) mtl = mtl.substr(0, dot);
  mtl += ".mtl";
  std::ofstream o(path);
  if (!o) return "cannot open " + path + " for writing";
  o << std::setprecision(9);
  o << "# Catmull-Clark control mesh (" << q.V.size() << " vertices, " << q.F.size() << " quads)\n";
  if (!texture.empty()) o << "mtllib " << BaseName(mtl) << "\n";
  for (const auto& v : q.V) o << "v " << v[0] << " " << v[1] << " " << v[2] << "\n";
  if (uv)
    for (const auto& w : wedgeUV)
      for (int c = 0; c < 4; ++c) o << "vt " << w[c][0] << " " << w[c][1] << "\n";
  if (!texture.empty()) o << "usemtl fitmap_displacement\n";
  for (size_t f = 0; f < q.F.size(); ++f) {
    o << "f";
    for (int c = 0; c < 4; ++c) {
      o << " " << q.F[f][c] + 1;
      if (uv) o << "/" << f * 4 + c + 1;
    }
    o << "\n";
  }
  if (!o) return "write error on " + path;
  if (!texture.empty()) {
    std::ofstream m(mtl);
    if (!m) return "cannot open " + mtl + " for writing";
    m << "newmtl fitmap_displacement\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\n"
      << "map_Kd " << texture << "\ndisp " << texture << "\n";
    if (!m) return "write error on " + mtl;
  }
  return {};
}

namespace {
// Binary little-endian PLY with polygon faces of N corners and optional per-vertex quality.
template <size_t N>
std::string WritePly(const std::string& path, const std::vector<Vec3>& V, const std::vector<std::array<int, N>>& F,
                     const std::vector<double>* quality) {
  const bool q = quality && quality->size() == V.size();
  std::ofstream o(path, std::ios::binary);
  if (!o) return "cannot open " + path + " for writing";
  o << "ply\nformat binary_little_endian 1.0\nelement vertex " << V.size()
    << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (q) o << "property float quality\n";
  o << "element face " << F.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (size_t i = 0; i < V.size(); ++i) {
    float b[4] = {float(V[i][0]), float(V[i][1]), float(V[i][2]), q ? float((*quality)[i]) : 0.f};
    o.write(reinterpret_cast<const char*>(b), q ? 16 : 12);
  }
  for (const auto& f : F) {
    unsigned char n = static_cast<unsigned char>(N);
    o.write(reinterpret_cast<const char*>(&n), 1);
    o.write(reinterpret_cast<const char*>(f.data()), sizeof(int) * N);
  }
  return o ? "" : "write error on " + path;
}
}  // namespace

std::string WritePlyWithQuality(const std::string& path, const TriData& m, const std::vector<double>* quality) {
  return WritePly(path, m.V, m.F, quality);
}

std::string WriteQuadPly(const std::string& path, const QuadData& q) {
  // MeshLab fans a polygon from its first corner: start each quad at its free diagonal.
  const std::vector<int> start = FreeDiagonalStarts(q);
  std::vector<Quad> F(q.F.size());
  for (size_t i = 0; i < F.size(); ++i)
    for (int c = 0; c < 4; ++c) F[i][c] = q.F[i][(c + start[i]) % 4];
  return WritePly(path, q.V, F, nullptr);
}

std::string ReportJson(const FitBakeResult& r, const std::vector<std::pair<std::string, double>>& extraTimes,
                       const std::vector<std::pair<std::string, double>>& extraMemory) {
  std::ostringstream o;
  if (!r.error.empty()) {
    o << "{\n  \"error\": \"" << Esc(r.error) << "\"\n}\n";
    return o.str();
  }
  double total = r.totalSeconds;
  for (const auto& t : extraTimes) total += t.second;
  std::string warnings = "[";
  for (size_t i = 0; i < r.warnings.size(); ++i) warnings += std::string(i ? ", " : "") + "\"" + Esc(r.warnings[i]) + "\"";
  warnings += "]";
  o << "{\n"
    << "  \"patches\": " << r.fit.patches << ",\n"
    << "  \"irregular_vertices\": " << r.fit.irregularVertices << ",\n"
    << "  \"degenerate_patches\": " << r.fit.degeneratePatches << ",\n"
    << "  \"unprojectable_pct\": " << Num(r.metrics.unprojectablePct) << ",\n"
    << "  \"warnings\": " << warnings << ",\n"
    << "  \"rms_limit_permille\": " << Num(r.metrics.rmsLimitPermille) << ",\n"
    << "  \"max_limit_permille\": " << Num(r.metrics.maxLimitPermille) << ",\n"
    << "  \"rms_displaced_permille\": " << Num(r.metrics.rmsDisplacedPermille) << ",\n"
    << "  \"max_displaced_permille\": " << Num(r.metrics.maxDisplacedPermille) << ",\n"
    << "  \"max_limit_to_reference_permille\": " << Num(r.metrics.maxLimitToRefPermille) << ",\n"
    << "  \"rms_displaced_area_permille\": " << Num(r.metrics.rmsDisplacedAreaPermille) << ",\n"
    << "  \"rms_displaced_to_reference_permille\": " << Num(r.metrics.rmsDisplacedToRefPermille) << ",\n"
    << "  \"max_displaced_to_reference_permille\": " << Num(r.metrics.maxDisplacedToRefPermille) << ",\n"
    << "  \"folded_triangles_displaced\": " << r.metrics.displacedFolds << ",\n"
    << "  \"folded_triangles_limit\": " << r.metrics.limitFolds << ",\n"
    << "  \"displacement_fit\": " << (r.displacementFit.fitted ? "true" : "false") << ",\n"
    << "  \"error_measure\": \"distance from every reference vertex to the closest point of the surface, "
       "unweighted per vertex, in 1/1000 of the reference bbox diagonal\",\n"
    << "  \"time_s\": {";
  bool first = true;
  auto put = [&](const std::string& k, double v) {
    o << (first ? "" : ",") << "\n    \"" << Esc(k) << "\": " << Num(v);
    first = false;
  };
  for (const auto& t : extraTimes) put(t.first, t.second);
  for (const auto& t : r.times) put(t.first, t.second);
  put("total", total);
  o << "\n  },\n"
    << "  \"peak_memory_mb\": " << Num(r.peakMemoryMb) << ",\n"
    << "  \"peak_memory_mb_per_stage\": {";
  first = true;
  for (const auto& m : extraMemory) put(m.first, m.second);
  for (const auto& m : r.memory) put(m.first, m.second);
  o << "\n  },\n"
    << "  \"reference_vertices\": " << r.referenceVertices << ",\n"
    << "  \"reference_faces\": " << r.referenceFaces << ",\n"
    << "  \"samples\": " << r.fit.samples << ",\n"
    << "  \"samples_per_side_min\": " << r.fit.minKUsed << ",\n"
    << "  \"samples_per_side_max\": " << r.fit.maxKUsed << ",\n"
    << "  \"iterations\": " << r.fit.iterations << ",\n"
    << "  \"ray_miss_pct\": " << Num(100 * r.fit.rayMissFraction) << ",\n"
    << "  \"rms_per_iteration\": [";
  for (size_t i = 0; i < r.fit.rmsPerIteration.size(); ++i) o << (i ? ", " : "") << Num(r.fit.rmsPerIteration[i]);
  o << "],\n"
    << "  \"texture_width\": " << r.atlas.width << ",\n"
    << "  \"texture_height\": " << r.atlas.height << ",\n"
    << "  \"texture_tile\": " << r.atlas.R << ",\n"
    << "  \"texture_tile_min\": "
    << (r.atlas.tileR.empty() ? 0 : *std::min_element(r.atlas.tileR.begin(), r.atlas.tileR.end())) << ",\n"
    << "  \"texture_tiles\": \"" << (r.atlas.adaptive ? "adaptive" : "uniform") << "\",\n"
    << "  \"texture_samples\": " << r.atlas.Samples() << "\n}\n";
  return o.str();
}

std::string WriteReportJson(const std::string& path, const FitBakeResult& r,
                            const std::vector<std::pair<std::string, double>>& extraTimes,
                            const std::vector<std::pair<std::string, double>>& extraMemory) {
  std::ofstream o(path);
  if (!o) return "cannot open " + path + " for writing";
  o << ReportJson(r, extraTimes, extraMemory);
  return o ? "" : "write error on " + path;
}

}  // namespace vcgext
