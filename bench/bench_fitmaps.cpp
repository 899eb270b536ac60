// Benchmark of vcgext::ComputeFitmaps (paper §3.1): median wall time of Fast mode over several
// runs, and its agreement with Reference mode on a random vertex subset (Spearman rank
// correlation of S and of M, median relative difference).
//
// Usage: bench_fitmaps [MESH] [--runs N] [--ref N] [--tau PCT] [--seed S] [--threads T] [--flip K] [--points P] [--spoints P] [--slevel L] [--coverage] [--ref-factor F] [--dump K] [--hash]
//   MESH defaults to $FITMAP_DATA_DIR/bunny00.off (else .deps/data/meshes/bunny00.off).
//   --ref-factor F: Reference mode's M sample factor (paper: 4).
//   --ref 0 skips the reference comparison; --dump K prints per-radius values of K subset vertices.
//   --hash prints an FNV-1a hash of the S and M arrays (fast, and reference on the subset): a refactor
//   must keep them bit for bit.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/fitmaps/fitmaps.h"
#include "vcg_ext/io/mesh_io.h"

namespace {

std::vector<double> Ranks(const std::vector<double>& x) {
  std::vector<int> idx(x.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return x[a] < x[b]; });
  std::vector<double> r(x.size());
  for (size_t i = 0; i < idx.size();) {
    size_t j = i;
    while (j + 1 < idx.size() && x[idx[j + 1]] == x[idx[i]]) ++j;
    for (size_t k = i; k <= j; ++k) r[idx[k]] = 0.5 * double(i + j);  // ties: mean rank
    i = j + 1;
  }
  return r;
}

double Pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = double(a.size());
  double ma = std::accumulate(a.begin(), a.end(), 0.0) / n, mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

double Spearman(const std::vector<double>& a, const std::vector<double>& b) { return Pearson(Ranks(a), Ranks(b)); }

// FNV-1a over the bytes of the values.
unsigned long long Fnv(const std::vector<double>& v) {
  unsigned long long h = 1469598103934665603ull;
  const auto* b = reinterpret_cast<const unsigned char*>(v.data());
  for (size_t i = 0; i < v.size() * sizeof(double); ++i) h = (h ^ b[i]) * 1099511628211ull;
  return h;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double MedianRelDiff(const std::vector<double>& fast, const std::vector<double>& ref) {
  std::vector<double> d;
  for (size_t i = 0; i < ref.size(); ++i)
    d.push_back(std::abs(fast[i] - ref[i]) / std::max(std::abs(ref[i]), 1e-300));
  return Median(d);
}

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  int runs = 5, refCount = 1000, threads = 0, dump = 0;
  bool hash = false;
  double refFactor = 4.0;
  vcgext::FitmapParams p;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
    if (a == "--runs") runs = std::max(1, std::atoi(next().c_str()));
    else if (a == "--ref") refCount = std::max(0, std::atoi(next().c_str()));
    else if (a == "--tau") p.tauPercent = std::atof(next().c_str());
    else if (a == "--seed") p.seed = unsigned(std::atoi(next().c_str()));
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--flip") p.fastFlipSamples = std::atoi(next().c_str());
    else if (a == "--points") p.fastPointsPerFit = std::atoi(next().c_str());
    else if (a == "--coverage") p.fastFlipEstimator = vcgext::FitmapParams::FlipEstimator::Coverage;
    else if (a == "--slevel") p.fastSLevel = std::atoi(next().c_str());
    else if (a == "--spoints") p.fastPointsPerSFit = std::atoi(next().c_str());
    else if (a == "--ref-factor") refFactor = std::atof(next().c_str());
    else if (a == "--dump") dump = std::atoi(next().c_str());
    else if (a == "--hash") hash = true;
    else if (a == "--help" || a == "-h") {
      std::printf("usage: %s [MESH] [--runs N] [--ref N] [--tau PCT] [--seed S] [--threads T]\n", argv[0]);
      return 0;
    } else path = a;
  }
  if (path.empty()) {
    const char* dir = std::getenv("FITMAP_DATA_DIR");
    path = std::string(dir ? dir : ".deps/data/meshes") + "/bunny00.off";
  }
  if (threads > 0) omp_set_num_threads(threads);
  vcgext::TMesh tm;
  std::string err = vcgext::LoadMesh(path, tm);
  if (!err.empty()) { std::fprintf(stderr, "cannot load %s: %s\n", path.c_str(), err.c_str()); return 1; }
  vcgext::TriData m;
  auto rep = vcgext::ImportTriangles(tm, m);
  if (!rep.error.empty()) { std::fprintf(stderr, "%s: %s\n", path.c_str(), rep.error.c_str()); return 1; }
  std::printf("mesh %s: %zu vertices, %zu faces; %d threads\n", path.c_str(), m.V.size(), m.F.size(),
              omp_get_max_threads());

  auto t0 = std::chrono::steady_clock::now();
  vcgext::EmbreeScene scene(m);
  double tScene = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!scene.Ok()) { std::fprintf(stderr, "embree: %s\n", scene.Error().c_str()); return 1; }

  std::vector<double> times, cpu;
  vcgext::FitmapResult fast;
  for (int r = 0; r < runs; ++r) {
    const std::clock_t c0 = std::clock();
    fast = vcgext::ComputeFitmaps(m, scene, p);
    cpu.push_back(double(std::clock() - c0) / CLOCKS_PER_SEC);
    if (!fast.error.empty()) { std::fprintf(stderr, "error: %s\n", fast.error.c_str()); return 1; }
    times.push_back(fast.seconds);
  }
  std::printf("last fast run: hierarchy done at %.3f s, coarse seeds done at %.3f s, total %.3f s; radius levels:",
              fast.secondsLevels, fast.secondsCoarse, fast.seconds);
  for (int l : fast.radiusLevel) std::printf(" %d", l);
  std::printf("\n");
  std::printf("fast mode: median %.3f s wall over %d runs (min %.3f, max %.3f; median CPU time %.3f s, "
              "all threads); Embree scene build %.3f s; %d levels; radii %.4g..%.4g\n",
              Median(times), runs,  *std::min_element(times.begin(), times.end()),
              *std::max_element(times.begin(), times.end()), Median(cpu), tScene, fast.levels, fast.radii.front(),
              fast.radii.back());
  {
    std::vector<double> S = fast.S, M = fast.M;
    std::printf("fast S: median %.4g, 5%% %.4g, 95%% %.4g; fast M: median %.4g; M = r_h on %.1f%%, "
                "M = r_0 on %.1f%%\n",
                Median(S), (std::sort(S.begin(), S.end()), S[S.size() / 20]), S[S.size() * 19 / 20], Median(M),
                100.0 * std::count(M.begin(), M.end(), fast.radii.back()) / M.size(),
                100.0 * std::count(M.begin(), M.end(), fast.radii.front()) / M.size());
  }
  if (hash) std::printf("hash fast S %016llx M %016llx\n", Fnv(fast.S), Fnv(fast.M));
  if (refCount == 0) return 0;

  vcgext::FitmapParams rp = p;
  rp.mode = vcgext::FitmapParams::Mode::Reference;
  rp.referenceSampleFactor = refFactor;
  std::vector<int> all(m.V.size());
  std::iota(all.begin(), all.end(), 0);
  std::mt19937 rng(12345);
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(std::min<size_t>(all.size(), size_t(refCount)));
  std::sort(all.begin(), all.end());
  rp.vertices = all;
  rp.keepPerRadius = dump > 0;
  vcgext::FitmapResult ref = vcgext::ComputeFitmaps(m, scene, rp);
  if (!ref.error.empty()) { std::fprintf(stderr, "error: %s\n", ref.error.c_str()); return 1; }
  if (hash) std::printf("hash reference S %016llx M %016llx\n", Fnv(ref.S), Fnv(ref.M));
  std::vector<double> fs, rs, fm, rm;
  for (int v : all) {
    fs.push_back(fast.S[v]);
    rs.push_back(ref.S[v]);
    fm.push_back(fast.M[v]);
    rm.push_back(ref.M[v]);
  }
  if (dump > 0) {  // per-radius diagnostics of the first `dump` subset vertices
    vcgext::FitmapParams fp = p;
    fp.keepPerRadius = true;
    vcgext::FitmapResult f2 = vcgext::ComputeFitmaps(m, scene, fp);
    const size_t H = ref.radii.size();
    for (int k = 0; k < dump && k < int(all.size()); ++k) {
      int v = all[k];
      std::printf("vertex %d: S fast %.4g ref %.4g, M fast %.4g ref %.4g\n  i  r        E_fast     E_ref      flip_fast  flip_ref\n",
                  v, f2.S[v], ref.S[v], f2.M[v], ref.M[v]);
      for (size_t i = 0; i < H; ++i)
        std::printf("  %zu  %.4f  %.4e  %.4e  %.4f  %.4f\n", i, ref.radii[i], f2.perRadiusE[v * H + i],
                    ref.perRadiusE[v * H + i], f2.perRadiusFlipped[v * H + i], ref.perRadiusFlipped[v * H + i]);
    }
  }
  int sameM = 0;
  for (size_t i = 0; i < fm.size(); ++i) sameM += fm[i] == rm[i];
  std::printf("reference mode (sample factor %g) on %zu random vertices: %.2f s (%.2f ms per vertex)\n",
              refFactor, all.size(), ref.seconds,
              1000.0 * ref.seconds / double(all.size()));
  std::printf("agreement fast vs reference: S Spearman %.4f, median rel. diff %.4f; "
              "M Spearman %.4f, median rel. diff %.4f, same radius on %.1f%%\n",
              Spearman(fs, rs), MedianRelDiff(fs, rs), Spearman(fm, rm), MedianRelDiff(fm, rm),
              100.0 * sameM / double(fm.size()));
  {
    std::vector<double> rm2 = rm;
    std::printf("reference M: median %.4g; M = r_h on %.1f%%, M = r_0 on %.1f%%\n", Median(rm2),
                100.0 * std::count(rm.begin(), rm.end(), ref.radii.back()) / rm.size(),
                100.0 * std::count(rm.begin(), rm.end(), ref.radii.front()) / rm.size());
  }
  return 0;
}
