// bench_decimate: the working resolution M' (vcgext::WorkingResolution, paper §4) of a mesh, on
// one thread and split in two halves on two threads (WorkingResolutionParams::splitMinFaces):
// wall time and the distance of the input's vertices to M' (RMS / max, ‰ of the bbox diagonal).
//
// Usage: bench_decimate MESH [maxFaces=100000] [runs=3]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "vcg_ext/core/decimate.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/fit/bake.h"
#include "vcg_ext/io/mesh_io.h"

using namespace vcgext;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_decimate MESH [maxFaces=100000] [runs=3]\n");
    return 2;
  }
  TMesh m;
  const std::string err = LoadMesh(argv[1], m);
  if (!err.empty()) {
    std::fprintf(stderr, "%s: %s\n", argv[1], err.c_str());
    return 1;
  }
  TriData d;
  const ImportReport rep = ImportTriangles(m, d, true);
  if (!rep.error.empty()) {
    std::fprintf(stderr, "%s: %s\n", argv[1], rep.error.c_str());
    return 1;
  }
  const int maxFaces = argc > 2 ? std::atoi(argv[2]) : 100000;
  const int runs = argc > 3 ? std::max(1, std::atoi(argv[3])) : 3;
  const double pm = 1000.0 / BBoxDiagonal(d.V);
  std::printf("%s: %zu triangles -> %d\n", argv[1], d.F.size(), maxFaces);
  for (int split : {0, 1}) {
    std::vector<double> secs;
    DecimateResult r;
    for (int k = 0; k < runs; ++k) {
      WorkingResolutionParams p;
      p.maxFaces = maxFaces + k;  // a new request each run (no reuse of the previous result)
      p.splitMinFaces = split ? 1 : 0;
      const auto t0 = std::chrono::steady_clock::now();
      r = WorkingResolution(d, p);
      secs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(secs.begin(), secs.end());
    const auto e = ReferenceToSurfaceError(d, r.mesh);
    std::printf("  %-26s %7zu faces  %6.2f s (median of %d)  input -> M' RMS %.4f max %.4f permille\n",
                split && r.split ? "two threads (split)" : "one thread", r.mesh.F.size(), secs[secs.size() / 2], runs,
                e.first * pm, e.second * pm);
  }
  return 0;
}
