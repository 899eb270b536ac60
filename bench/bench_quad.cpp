// Benchmark of vcgext::SimplifyToQuads (Fitmaps §3.2–3.4) on a real scan: patches, irregular
// vertices, valence histogram, projectability of the limit surface, time per stage (median of
// several runs) and peak memory.
//
// Usage: bench_quad [MESH] [--runs N] [--tau PCT[,PCT...]] [--threads T] [--standin] [--target N]
//                   [--obj PREFIX]
//                   [--rh PCT] [--rmin PCT] [--nradii N] [--mcap PCT] [--valence W] [--mscale X] [--no-m] [--no-fit]
//   MESH defaults to $FITMAP_DATA_DIR/bunny00.off (else /tmp/cgal/data/meshes/bunny00.off).
//   --tau: tau values in percent (default 1,10); Fitmaps from vcgext::ComputeFitmaps (Fast mode).
//   --no-area: the coverage guard's area trigger off (QuadSimplifyParams::coverageUnprojectablePct = 0).
//   --no-fit: skip the §3.5 global fit (vcgext::FitCatmullClark) before the second projectability figure.
//   --target N: stop at N patches; --no-m: no M-fitmap test (with --target: a fixed budget).
//   --rh PCT: the Fitmaps' largest radius r_h, % of the bbox diagonal (default 25, the paper's).
//   --rmin PCT: FitmapParams::minRadiusPercent (0 = the paper's radii from the average edge length);
//   --nradii N: FitmapParams::numRadii (the paper's grid).
//   --mcap PCT: clamp the M-fitmap to PCT % of the bbox diagonal (a patch-size cap, experiments).
//   --valence W: QuadSimplifyParams::valenceWeight (collapse cost x (1 + W)^(valence defect change)).
//   --mscale X: multiply the M-fitmap by X (emulates a coarser M-fitmap scale, e.g. earlier Fitmaps).
//   --dev F: QuadSimplifyParams::deviationFactor (geometric guard, fraction of F_M; 0 = off);
//   --devcap PCT: QuadSimplifyParams::maxDeviationPercent.
//   --ray PCT: max projection ray length, % of the bbox diagonal (default 5).
//   --standin: crude curvature-based stand-ins for S and M instead of ComputeFitmaps.
//   --obj PREFIX: writes PREFIX_tau<PCT>.obj (control mesh, real quads) of the last run.
//   --dump-unreached FILE: per input triangle "cx cy cz reached(0/1)" (last tau).
//
// Projectability: the exact limit surface (vcgext::LimitSurface, OpenSubdiv Bfr) is sampled on a
// k x k grid per patch (k from the patch's area: ~16 samples per input triangle); each sample casts a ray
// along its limit normal (either side, within 5% of the bbox diagonal); an input triangle counts
// as reached if some ray hits it with agreeing normals. Reported as % of the input area.
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/fit/cc_fit.h"
#include "vcg_ext/fitmaps/fitmaps.h"
#include "vcg_ext/io/mesh_io.h"
#include "vcg_ext/quad/quad_simplify.h"
#include "vcg_ext/subdiv/limit_surface.h"

namespace {

using vcgext::Vec3;
double rayPct = 5.0;

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double PeakMB() {
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;
}

// Crude stand-ins: S ~ sqrt of a normal-variation curvature estimate (1/length), M ~ c / kappa.
void StandIns(const vcgext::TriData& m, double tauPct, std::vector<double>& S, std::vector<double>& M) {
  auto N = vcgext::VertexNormals(m);
  auto adj = vcgext::VertexVertexAdjacency(m.F, int(m.V.size()));
  double diag = vcgext::BBoxDiagonal(m.V), r0 = vcgext::AverageEdgeLength(m);
  std::vector<double> k(m.V.size(), 0.0);
  for (size_t i = 0; i < m.V.size(); ++i)
    for (const int* j = adj.Begin(int(i)); j != adj.End(int(i)); ++j) {
      double d = (m.V[*j] - m.V[i]).norm();
      if (d > 0) k[i] = std::max(k[i], (N[*j] - N[i]).norm() / d);
    }
  S.resize(m.V.size());
  M.resize(m.V.size());
  double c = 0.3 * std::sqrt(std::max(tauPct, 0.1));
  for (size_t i = 0; i < m.V.size(); ++i) {
    S[i] = std::sqrt(k[i] / diag) + 1e-3 / diag;
    M[i] = std::clamp(c / std::max(k[i], 1e-12), r0, 0.25 * diag);
  }
}

double Projectability(const vcgext::TriData& in, const vcgext::EmbreeScene& scene, const vcgext::QuadData& q,
                      const std::string& dumpUnreached = "") {
  vcgext::LimitSurface ls = vcgext::LimitSurface::FromQuads(q);
  if (!ls.Ok()) return -1;
  auto FN = vcgext::FaceNormals(in);
  double diag = vcgext::BBoxDiagonal(in.V);
  std::vector<char> hit(in.F.size(), 0);
  // samples per patch proportional to its area (control-quad area as the estimate): ~16 samples
  // per input triangle overall
  std::vector<double> area(q.F.size());
  double total = 0;
  for (size_t f = 0; f < q.F.size(); ++f) {
    const auto& x = q.F[f];
    area[f] = 0.5 * (q.V[x[2]] - q.V[x[0]]).cross(q.V[x[3]] - q.V[x[1]]).norm();
    total += area[f];
  }
#pragma omp parallel for schedule(dynamic, 4)
  for (int f = 0; f < ls.NumFaces(); ++f) {
    int k = std::max(4, int(std::ceil(std::sqrt(16.0 * double(in.F.size()) * area[f] / std::max(total, 1e-300)))));
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        Vec3 P, Du, Dv;
        if (!ls.Evaluate(f, (i + 0.5) / k, (j + 0.5) / k, q.V, &P, &Du, &Dv)) continue;
        Vec3 n = Du.cross(Dv);
        if (!(n.norm() > 0)) continue;
        n.normalize();
        auto h = scene.IntersectLine(P, n, rayPct / 100.0 * diag);
        if (h.valid && FN[h.face].dot(n) > 0) hit[h.face] = 1;
      }
  }
  double a = 0, ah = 0;
  for (size_t t = 0; t < in.F.size(); ++t) {
    const auto& f = in.F[t];
    double ar = 0.5 * (in.V[f[1]] - in.V[f[0]]).cross(in.V[f[2]] - in.V[f[0]]).norm();
    a += ar;
    if (hit[t]) ah += ar;
  }
  if (!dumpUnreached.empty())
    if (FILE* fo = std::fopen(dumpUnreached.c_str(), "w")) {
      for (size_t t = 0; t < in.F.size(); ++t) {
        Vec3 c = (in.V[in.F[t][0]] + in.V[in.F[t][1]] + in.V[in.F[t][2]]) / 3.0;
        std::fprintf(fo, "%g %g %g %d\n", c[0], c[1], c[2], int(hit[t]));
      }
      std::fclose(fo);
    }
  return a > 0 ? 100.0 * ah / a : 0;
}

void WriteObj(const std::string& path, const vcgext::QuadData& q) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return;
  for (auto& p : q.V) std::fprintf(f, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
  for (auto& x : q.F) std::fprintf(f, "f %d %d %d %d\n", x[0] + 1, x[1] + 1, x[2] + 1, x[3] + 1);
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  std::string mesh;
  const char* env = std::getenv("FITMAP_DATA_DIR");
  mesh = std::string(env ? env : "/tmp/cgal/data/meshes") + "/bunny00.off";
  int runs = 3, threads = 2, target = 0, nradii = -1;
  bool standin = false, finalFit = true, useM = true, noArea = false;
  double mscale = 1.0, dev = -1, devcap = -1, rh = -1, rmin = -1, mcap = -1, valenceWeight = -1;
  std::string objPrefix, dumpUnreached;
  std::vector<double> taus{1.0, 10.0};
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
    else if (a == "--target" && i + 1 < argc) target = std::atoi(argv[++i]);
    else if (a == "--standin") standin = true;
    else if (a == "--no-fit") finalFit = false;
    else if (a == "--no-area") noArea = true;
    else if (a == "--no-m") useM = false;
    else if (a == "--dev" && i + 1 < argc) dev = std::atof(argv[++i]);
    else if (a == "--devcap" && i + 1 < argc) devcap = std::atof(argv[++i]);
    else if (a == "--mscale" && i + 1 < argc) mscale = std::atof(argv[++i]);
    else if (a == "--rh" && i + 1 < argc) rh = std::atof(argv[++i]);
    else if (a == "--rmin" && i + 1 < argc) rmin = std::atof(argv[++i]);
    else if (a == "--nradii" && i + 1 < argc) nradii = std::atoi(argv[++i]);
    else if (a == "--mcap" && i + 1 < argc) mcap = std::atof(argv[++i]);
    else if (a == "--valence" && i + 1 < argc) valenceWeight = std::atof(argv[++i]);
    else if (a == "--ray" && i + 1 < argc) rayPct = std::atof(argv[++i]);
    else if (a == "--obj" && i + 1 < argc) objPrefix = argv[++i];
    else if (a == "--dump-unreached" && i + 1 < argc) dumpUnreached = argv[++i];
    else if (a == "--tau" && i + 1 < argc) {
      taus.clear();
      std::string s = argv[++i];
      size_t pos = 0;
      while (pos < s.size()) {
        size_t e = s.find(',', pos);
        taus.push_back(std::atof(s.substr(pos, e - pos).c_str()));
        if (e == std::string::npos) break;
        pos = e + 1;
      }
    } else if (a[0] != '-') mesh = a;
    else { std::fprintf(stderr, "unknown option %s\n", a.c_str()); return 2; }
  }
  omp_set_num_threads(threads);
  vcgext::TMesh tm;
  std::string err = vcgext::LoadMesh(mesh, tm);
  if (!err.empty()) { std::fprintf(stderr, "load %s: %s\n", mesh.c_str(), err.c_str()); return 1; }
  vcgext::TriData in;
  auto rep = vcgext::ImportTriangles(tm, in);
  if (!rep.error.empty()) { std::fprintf(stderr, "import: %s\n", rep.error.c_str()); return 1; }
  vcgext::EmbreeScene scene(in);
  std::printf("mesh %s: %zu vertices, %zu triangles; %d threads, %d runs (median)\n", mesh.c_str(), in.V.size(),
              in.F.size(), threads, runs);
  for (double tau : taus) {
    std::vector<double> S, M;
    double tFit = 0;
    if (standin) {
      StandIns(in, tau, S, M);
    } else {
      vcgext::FitmapParams fp;
      fp.tauPercent = tau;
      if (rh > 0) fp.maxRadiusPercent = rh;
      if (rmin > 0) fp.minRadiusPercent = rmin;
      if (nradii > 0) fp.numRadii = nradii;
      auto t0 = std::chrono::steady_clock::now();
      auto fr = vcgext::ComputeFitmaps(in, scene, fp);
      tFit = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!fr.error.empty()) { std::fprintf(stderr, "fitmaps: %s\n", fr.error.c_str()); return 1; }
      S = fr.S;
      M = fr.M;
      std::vector<double> sm = S, mm = M;
      std::printf("fitmaps: median S %.4g, median M %.4g (bbox diagonal %.4g)\n", Median(sm), Median(mm),
                  vcgext::BBoxDiagonal(in.V));
    }
    for (double& x : M) x *= mscale;
    if (mcap > 0) { double d = vcgext::BBoxDiagonal(in.V); for (double& x : M) x = std::min(x, mcap * d / 100); }
    {
      std::vector<double> m(M);
      std::sort(m.begin(), m.end());
      double d = vcgext::BBoxDiagonal(in.V);
      auto pc = [&](double q) { return 100.0 * m[size_t(q * double(m.size() - 1))] / d; };
      std::printf("\n  M-fitmap (%% bbox diagonal): 10%% %.2f, median %.2f, 90%% %.2f\n", pc(0.1), pc(0.5), pc(0.9));
    }
    vcgext::QuadSimplifyParams p;
    if (noArea) p.coverageUnprojectablePct = 0;
    p.targetPatches = target;
    p.useMFitmap = useM;
    if (dev >= 0) p.deviationFactor = dev;
    if (devcap >= 0) p.maxDeviationPercent = devcap;
    if (valenceWeight >= 0) p.valenceWeight = valenceWeight;
    std::vector<double> tq, tinit, tsimp, ttot, tcpu;
    vcgext::QuadSimplifyResult r;
    for (int run = 0; run < runs; ++run) {
      std::clock_t c0 = std::clock();
      r = vcgext::SimplifyToQuads(in, scene, S, M, p);
      tcpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
      if (!r.error.empty()) { std::fprintf(stderr, "simplify: %s\n", r.error.c_str()); return 1; }
      tq.push_back(r.secondsTriToQuad);
      tinit.push_back(r.secondsInitialFit);
      tsimp.push_back(r.secondsSimplify);
      ttot.push_back(r.secondsTotal);
    }
    double proj = Projectability(in, scene, r.quads, dumpUnreached);
    double projFit = -1, tFinal = 0;
    if (finalFit) {
      auto t0 = std::chrono::steady_clock::now();
      vcgext::FitResult fr = vcgext::FitCatmullClark(r.quads, in, scene);
      tFinal = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (fr.error.empty()) projFit = Projectability(in, scene, fr.control);
    }
    std::printf("\ntau %.3g%% (%s fitmaps%s)\n", tau, standin ? "stand-in" : "ComputeFitmaps",
                standin ? "" : (", " + std::to_string(tFit).substr(0, 5) + " s").c_str());
    std::printf("  tri-to-quad      %s, %d initial quads\n", vcgext::quad::ToString(r.triToQuadPath), r.initialPatches);
    std::printf("  patches          %d\n", r.patches);
    if (r.budgetRelaxations > 0)
      std::printf("  budget           first pass %d patches; thin-part guard relaxed %d time(s), factor %.3g (0: off)\n",
                  r.budgetFromPatches, r.budgetRelaxations, r.budgetDeviationFactor);
    std::printf("  irregular        %d of %zu vertices\n", r.irregularVertices, r.quads.V.size());
    std::printf("  valences        ");
    for (size_t v = 0; v < r.valenceHistogram.size(); ++v)
      if (r.valenceHistogram[v]) std::printf(" %zu:%d", v, r.valenceHistogram[v]);
    std::printf("\n  operations       %d collapses, %d swaps, %d doublets, %d boundary corners\n", r.collapses, r.swaps,
                r.doublets, r.boundaryCorners);
    std::printf("  refused          %d by M-fitmap, %d topology, %d flip, %d geometric guard\n", r.rejectedByM,
                r.rejectedTopology, r.rejectedFlip, r.rejectedDeviation);
    std::printf("  parallel checks  %.0f %% of the steps (AdaptiveParallelism)\n", 100 * r.parallelStepShare);
    std::printf("  flipped          %d patches, %d vertices\n", r.flippedPatches, r.flippedVertices);
    if (r.coverageRelayouts > 0)
      std::printf("  coverage guard   %d layout passes from %d patches (guard's figures: RMS %.3g, unreached %.3f%%)\n",
                  r.coverageRelayouts, r.coverageFromPatches, r.coverageFromRms, r.coverageFromUnprojectablePct);
    if (r.layoutUnprojectablePct >= 0)
      std::printf("  unreached        %.3f%% (the guard's estimate on the kept cage)\n", r.layoutUnprojectablePct);
    std::printf("  projectable      %.2f%% of the input area (control mesh as simplified, limit interpolates)\n", proj);
    if (finalFit)
      std::printf("  projectable      %.2f%% after the global fit of §3.5 (vcgext::FitCatmullClark, %.2f s)\n", projFit, tFinal);
    std::printf("  initial solve    %d iterations, max residual %.3g\n", r.initialSolveIterations, r.initialSolveResidual);
    std::printf("  time (median)    tri-to-quad %.3f s, initial fit %.3f s, simplification %.3f s, total %.3f s wall"
                " (process CPU %.3f s; the machine is shared, CPU time is the steadier figure)\n",
                Median(tq), Median(tinit), Median(tsimp), Median(ttot), Median(tcpu));
    if (!objPrefix.empty()) WriteObj(objPrefix + "_tau" + std::to_string(int(tau)) + ".obj", r.quads);
  }
  std::printf("\npeak memory %.1f MB\n", PeakMB());
  return 0;
}
