// patch_layout: the Catmull-Clark limit surface of a quad control mesh, one colour per patch, as
// an ASCII PLY with per-vertex colours (vertices not shared between patches, so the patch
// layout shows as flat colour regions). Used for the README pictures.
// Usage: patch_layout CONTROL.ply OUT.ply [segments=8]
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/fit/bake.h"
#include "vcg_ext/io/mesh_io.h"
#include "vcg_ext/subdiv/limit_surface.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s CONTROL.ply OUT.ply [segments=8]\n", argv[0]);
    return 2;
  }
  const int N = argc > 3 ? std::max(1, std::atoi(argv[3])) : 8;
  vcgext::TMesh m;
  std::string err = vcgext::LoadMesh(argv[1], m);
  vcgext::QuadData q;
  if (err.empty()) err = vcgext::ImportQuads(m, q);
  if (!err.empty()) { std::fprintf(stderr, "%s\n", err.c_str()); return 1; }
  vcgext::LimitSurface ls = vcgext::LimitSurface::FromQuads(q);
  if (!ls.Ok()) { std::fprintf(stderr, "%s\n", ls.Error().c_str()); return 1; }
  vcgext::LimitTessellation t = vcgext::TessellateLimit(ls, q.V, N);
  // Faces are stored patch by patch, 2·N² each.
  const size_t perPatch = size_t(2) * N * N;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> U(60, 255);
  std::vector<std::array<int, 3>> colour(q.F.size());
  for (auto& c : colour) c = {U(rng), U(rng), U(rng)};
  std::ofstream o(argv[2]);
  o << "ply\nformat ascii 1.0\nelement vertex " << 3 * t.mesh.F.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
       "property uchar blue\nelement face "
    << t.mesh.F.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (size_t f = 0; f < t.mesh.F.size(); ++f) {
    const auto& c = colour[std::min(f / perPatch, colour.size() - 1)];
    for (int k = 0; k < 3; ++k) {
      const auto& p = t.mesh.V[t.mesh.F[f][k]];
      o << p[0] << " " << p[1] << " " << p[2] << " " << c[0] << " " << c[1] << " " << c[2] << "\n";
    }
  }
  for (size_t f = 0; f < t.mesh.F.size(); ++f) o << "3 " << 3 * f << " " << 3 * f + 1 << " " << 3 * f + 2 << "\n";
  std::printf("%zu patches, %zu triangles -> %s\n", q.F.size(), t.mesh.F.size(), argv[2]);
  return o ? 0 : 1;
}
