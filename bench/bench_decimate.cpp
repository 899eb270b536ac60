// bench_decimate: the working resolution M' (vcgext::WorkingResolution, paper §4) of a mesh, on
// one thread and split in two halves on two threads (WorkingResolutionParams::splitMinFaces):
// wall and CPU time (all threads; steadier than wall time on a shared machine) and the distance
// of the input's vertices to M' (RMS / max, ‰ of the bbox diagonal).
//
// With "compare", also with vcglib's own priority evaluation (WorkingResolutionParams::vcgPriority;
// the same meshes, the time the one-pass evaluation saves).
//
// Usage: bench_decimate MESH [maxFaces=100000] [runs=3] [compare]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
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
    std::fprintf(stderr, "usage: bench_decimate MESH [maxFaces=100000] [runs=3] [compare]\n");
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
  const bool compare = argc > 4 && std::string(argv[4]) == "compare";
  const double pm = 1000.0 / BBoxDiagonal(d.V);
  std::printf("%s: %zu triangles -> %d\n", argv[1], d.F.size(), maxFaces);
  // Each configuration: split in two halves or not, one-pass priority or vcglib's own. Runs are
  // interleaved (run k of every configuration, then run k + 1) so that load hits them alike.
  struct Config {
    bool split, vcgPriority;
    std::vector<double> secs, cpu;
    DecimateResult r;
  };
  std::vector<Config> configs;
  for (int split : {0, 1})
    for (int vcg = 0; vcg <= (compare ? 1 : 0); ++vcg) configs.push_back({split == 1, vcg == 1, {}, {}, {}});
  for (int k = 0; k < runs; ++k)
    for (Config& c : configs) {
      WorkingResolutionParams p;
      p.maxFaces = maxFaces + k;  // a new request each run (no reuse of the previous result)
      p.splitMinFaces = c.split ? 1 : 0;
      p.vcgPriority = c.vcgPriority;
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      c.r = WorkingResolution(d, p);
      c.secs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      c.cpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
    }
  for (Config& c : configs) {
    std::sort(c.secs.begin(), c.secs.end());
    std::sort(c.cpu.begin(), c.cpu.end());
    const auto e = ReferenceToSurfaceError(d, c.r.mesh);
    const std::string name = std::string(c.split && c.r.split ? "two threads (split)" : "one thread") +
                             (c.vcgPriority ? ", vcglib priority" : "");
    std::printf("  %-36s %7zu faces  %6.2f s wall, %6.2f s CPU (medians of %d)  input -> M' RMS %.4f max %.4f permille\n",
                name.c_str(), c.r.mesh.F.size(), c.secs[c.secs.size() / 2], c.cpu[c.cpu.size() / 2], runs, e.first * pm,
                e.second * pm);
  }
  return 0;
}
