// Benchmark of the Loop surrogate kernel: evaluations per second at random points of a real
// mesh (extraordinary regions included) and adaptive refinement of fandisk to ~250k triangles.
// Usage: bench_loop [mesh.off] [runs]   (default: FITMAP data fandisk.off, 5 runs; medians)
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "vcg_ext/core/mesh_types.h"
#include "vcg_ext/io/mesh_io.h"
#include "vcg_ext/loop/loop_surface.h"
#include "vcg_ext/loop/loop_tools.h"

static double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int main(int argc, char** argv) {
  std::string path = argc > 1 ? argv[1] : "/tmp/cgal/data/meshes/fandisk.off";
  int runs = argc > 2 ? std::atoi(argv[2]) : 5;
  vcgext::TMesh m;
  std::string err = vcgext::LoadMesh(path, m);
  if (!err.empty()) { std::fprintf(stderr, "%s\n", err.c_str()); return 1; }
  vcgext::TriData d;
  auto ir = vcgext::ImportTriangles(m, d);
  if (!ir.error.empty()) { std::fprintf(stderr, "%s\n", ir.error.c_str()); return 1; }
  auto t0 = std::chrono::steady_clock::now();
  vcgext::LoopSurface s(d);
  double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!s.Ok()) { std::fprintf(stderr, "%s\n", s.Error().c_str()); return 1; }
  std::printf("mesh %s: %d vertices, %d faces, %d irregular faces, %d hard edges, %d hard vertices\n", path.c_str(),
              s.NumVertices(), s.NumFaces(), s.NumIrregularFaces(), s.NumHardEdges(), s.NumCornerVertices());
  std::printf("build %.3f s, cache %.1f MB, threads %d\n", build, s.CacheBytes() / 1e6, omp_get_max_threads());
  const int N = 4000000;
  std::vector<int> f(N);
  std::vector<double> v(N), w(N);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(0, 1);
  for (int i = 0; i < N; ++i) {
    f[i] = int(rng() % s.NumFaces());
    v[i] = U(rng); w[i] = U(rng);
    if (v[i] + w[i] > 1) { v[i] = 1 - v[i]; w[i] = 1 - w[i]; }
  }
  for (int pass = 0; pass < 2; ++pass)
  for (int order = 0; order <= 2; order += 2) {
    if (pass == 1 && order == 0) {  // second pass: the same points sorted by face (coherent queries)
      std::vector<int> idx(N);
      for (int i = 0; i < N; ++i) idx[i] = i;
      std::sort(idx.begin(), idx.end(), [&](int a, int b) { return f[a] < f[b]; });
      std::vector<int> f2(N);
      std::vector<double> v2(N), w2(N);
      for (int i = 0; i < N; ++i) { f2[i] = f[idx[i]]; v2[i] = v[idx[i]]; w2[i] = w[idx[i]]; }
      f.swap(f2); v.swap(v2); w.swap(w2);
    }
    std::vector<double> rate;
    for (int r = 0; r < runs; ++r) {
      double sink = 0;
      auto a = std::chrono::steady_clock::now();
#pragma omp parallel for reduction(+ : sink) schedule(static, 4096)
      for (int i = 0; i < N; ++i) {
        vcgext::LoopEval e;
        s.Evaluate(f[i], v[i], w[i], e, order);
        sink += e.P[0] + e.Dvv[1];
      }
      double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
      rate.push_back(N / t);
      if (sink == 12345.678) std::printf(" ");
    }
    std::printf("%s evaluate order %d (position%s): median %.2f M evals/s over %d runs of %d random points\n", pass ? "face-sorted" : "random order", order,
                order ? " + 1st + 2nd derivatives + normal" : "", Median(rate) / 1e6, runs, N);
  }
  std::vector<double> times;
  int tris = 0;
  vcgext::LoopRefineParams rp;
  rp.targetFaces = 250000;
  for (int r = 0; r < runs; ++r) {
    auto res = vcgext::RefineLoopSurface(s, rp);
    times.push_back(res.seconds);
    tris = int(res.mesh.F.size());
    if (r == 0)
      std::printf("refine: passes %d insertions %d edge splits %d swaps %d\n", res.passes, res.insertions, res.edgeSplits,
                  res.swaps);
  }
  double tm = Median(times);
  std::printf("adaptive refinement to %d triangles: median %.3f s (%.0f triangles/s) over %d runs\n", tris, tm, tris / tm,
              runs);
  return 0;
}
