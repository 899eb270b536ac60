// midpoint_subdivide: splits every triangle into four at its edge midpoints, `levels` times
// (the shape stays exactly the same, the triangle count grows 4x per level). Makes the dense
// inputs of bench/dense_bench.sh and of the tri-to-quad property tests.
// Usage: midpoint_subdivide IN.off OUT.off [levels=1]
// Writes a binary-free ASCII OFF (MeshLab 2020.09 reads it); float coordinates as %.9g.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/algorithms/refine.h>

#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/io/mesh_io.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s IN.off OUT.off [levels=1]\n", argv[0]);
    return 2;
  }
  const int levels = argc > 3 ? std::atoi(argv[3]) : 1;
  if (levels < 0 || levels > 6) { std::fprintf(stderr, "levels must be in 0..6\n"); return 2; }
  vcgext::TMesh m;
  std::string err = vcgext::LoadMesh(argv[1], m);
  if (!err.empty()) { std::fprintf(stderr, "%s: %s\n", argv[1], err.c_str()); return 1; }
  for (int l = 0; l < levels; ++l) {  // vcglib's edge-midpoint refinement, every edge (threshold 0)
    vcg::tri::UpdateTopology<vcgext::TMesh>::FaceFace(m);
    // vcglib's refinement walks face-face adjacency and crashes on an edge of three faces or more
    // (duplicate faces): say so instead
    if (const int nm = vcg::tri::Clean<vcgext::TMesh>::CountNonManifoldEdgeFF(m); nm > 0) {
      std::fprintf(stderr, "%s: %d non-manifold edges (more than two faces); midpoint refinement needs a manifold mesh\n",
                   argv[1], nm);
      return 1;
    }
    vcg::tri::Refine<vcgext::TMesh>(m, vcg::tri::MidPoint<vcgext::TMesh>(&m), 0);
  }
  vcgext::TriData t;
  err = vcgext::ImportTriangles(m, t, /*allowPolygonal=*/true).error;
  if (!err.empty()) { std::fprintf(stderr, "%s: %s\n", argv[1], err.c_str()); return 1; }
  FILE* o = std::fopen(argv[2], "w");
  if (!o) { std::fprintf(stderr, "cannot write %s\n", argv[2]); return 1; }
  std::fprintf(o, "OFF\n%zu %zu 0\n", t.V.size(), t.F.size());
  for (const auto& p : t.V) std::fprintf(o, "%.9g %.9g %.9g\n", p[0], p[1], p[2]);
  for (const auto& f : t.F) std::fprintf(o, "3 %d %d %d\n", f[0], f[1], f[2]);
  return std::fclose(o) == 0 ? 0 : 1;
}
