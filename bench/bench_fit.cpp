// bench_fit: final Catmull-Clark fit + bake on a real scan, printed like the paper's Table 1
// (patches, irregular vertices, unprojectable %, RMS limit / displaced error in ‰ of the bbox
// diagonal) and Table 2 (per-stage wall time), plus peak memory. Median of several runs.
//
// Usage: bench_fit REFERENCE CONTROL [runs=3] [outdir] [key=value ...]
//   REFERENCE  dense triangle mesh (e.g. bunny00.off)
//   CONTROL    a quad mesh as OBJ (`f a b c d`) or PLY (MeshLab's faux-edge triangle pairs as
//              saved by `meshlabserver ... -m ff`, or quad faces), or a coarse triangle mesh (OFF/PLY/OBJ
//              with triangles) that is turned into quads by one Catmull-Clark-style split
//              (each triangle -> 3 quads through edge midpoints and its centroid).
//   outdir     if given, writes control.obj/.mtl, limit.ply, displaced.ply, displacement.png/.json,
//              normal.png and report.json there (last run).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/vcg_bridge.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/fit/bake.h"
#include "vcg_ext/fit/fit_io.h"
#include "vcg_ext/io/mesh_io.h"

using namespace vcgext;

namespace {

bool LoadTri(const std::string& path, TriData& d) {
  TMesh m;
  std::string err = LoadMesh(path, m);
  if (!err.empty()) { std::fprintf(stderr, "%s: %s\n", path.c_str(), err.c_str()); return false; }
  ImportReport rep = ImportTriangles(m, d, true);
  if (!rep.error.empty()) { std::fprintf(stderr, "%s: %s\n", path.c_str(), rep.error.c_str()); return false; }
  return true;
}

bool LoadQuadObj(const std::string& path, QuadData& q) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") { double x, y, z; s >> x >> y >> z; q.V.emplace_back(x, y, z); }
    if (tag == "f") {
      std::vector<int> idx;
      std::string tok;
      while (s >> tok) idx.push_back(std::stoi(tok.substr(0, tok.find('/'))) - 1);
      if (idx.size() != 4) return false;
      q.F.push_back({idx[0], idx[1], idx[2], idx[3]});
    }
  }
  return !q.F.empty();
}

// A pure-quad layer as MeshLab saves it (PLY triangle pairs with faux-edge flags, `-m ff`) or a
// quad PLY: vcglib reads polygons as faux-edge fans, ImportQuads pairs them back.
bool LoadQuadLayer(const std::string& path, QuadData& q) {
  TMesh m;
  if (!LoadMesh(path, m).empty()) return false;
  return ImportQuads(m, q).empty();
}

QuadData SplitTrianglesToQuads(const TriData& t) {
  QuadData q;
  q.V = t.V;
  std::map<std::pair<int, int>, int> mid;
  auto m = [&](int a, int b) {
    auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    q.V.push_back(0.5 * (t.V[a] + t.V[b]));
    mid[key] = int(q.V.size()) - 1;
    return int(q.V.size()) - 1;
  };
  for (const auto& f : t.F) {
    q.V.push_back((t.V[f[0]] + t.V[f[1]] + t.V[f[2]]) / 3.0);
    int c = int(q.V.size()) - 1;
    for (int k = 0; k < 3; ++k) q.F.push_back({f[k], m(f[k], f[(k + 1) % 3]), c, m(f[(k + 2) % 3], f[k])});
  }
  return q;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  // Positional arguments, then optional key=value overrides of FitBakeParams (see usage).
  std::vector<std::string> pos;
  FitBakeParams p;
  int shuffleSeed = 0;  // > 0: the control mesh's faces permuted and each quad's corners rotated
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto eq = a.find('=');
    if (eq == std::string::npos) { pos.push_back(a); continue; }
    const std::string k = a.substr(0, eq);
    const double v = std::atof(a.c_str() + eq + 1);
    if (k == "R") p.textureResolution = int(v);
    else if (k == "iters") p.fit.maxIterations = int(v);
    else if (k == "vw") p.fit.vertexWeight = v;
    else if (k == "damp") p.fit.dampingWeight = v;
    else if (k == "spv") p.fit.samplesPerVertex = v;
    else if (k == "minimp") p.fit.minImprovement = v;
    else if (k == "tw") p.fit.tangentWeight = v;
    else if (k == "dw") p.fit.dataWeight = v;
    else if (k == "sw") p.fit.sampleWeight = v;
    else if (k == "smooth") p.fit.smoothWeight = v;
    else if (k == "fps") p.fit.footpointSegments = int(v);
    else if (k == "dfit") p.fitDisplacement = v != 0;
    else if (k == "adapt") p.adaptiveTiles = v != 0;
    else if (k == "N") p.limitSegments = int(v);
    else if (k == "Nm") p.metricSegments = int(v);
    else if (k == "danchor") p.displacementFit.anchorWeight = v;
    else if (k == "diters") p.displacementFit.iterations = int(v);
    else if (k == "keep") p.fit.keepLowestDataRms = v != 0;
    else if (k == "shuffle") shuffleSeed = int(v);
    else if (k == "method") p.fit.method = v == 0 ? FitMethod::PointToPoint : FitMethod::TangentDistance;
    else { std::fprintf(stderr, "unknown option %s\n", k.c_str()); return 2; }
  }
  if (pos.size() < 2) {
    std::fprintf(stderr,
                 "usage: %s REFERENCE CONTROL [runs=3] [outdir] [R=tile] [iters=n] [vw=vertex weight] [damp=w] "
                 "[spv=samples per vertex] [minimp=fraction] [tw=tangent weight] [dw=data weight] [sw=sample weight] [smooth=control-net Laplacian weight] [fps=foot-point segments] [N=limit segments] [Nm=metric segments, 0 auto] [dfit=0|1 least-squares displacement] [adapt=0|1 tile size per patch] [danchor=anchor weight] [diters=rounds] "
                 "[method=0 point-to-point | 1 tangent distance] [keep=1 lowest data RMS | 0 lowest objective] [shuffle=seed: permute the control faces and rotate their corners, the same surface]\n",
                 argv[0]);
    return 2;
  }
  const std::string refPath = pos[0], ctrlPath = pos[1];
  const int runs = pos.size() > 2 ? std::max(1, std::atoi(pos[2].c_str())) : 3;
  const std::string outdir = pos.size() > 3 ? pos[3] : "";
  TriData ref;
  if (!LoadTri(refPath, ref)) return 1;
  QuadData ctrl;
  const bool isObj = ctrlPath.size() > 4 && ctrlPath.substr(ctrlPath.size() - 4) == ".obj";
  const bool isPly = ctrlPath.size() > 4 && ctrlPath.substr(ctrlPath.size() - 4) == ".ply";
  if (!(isObj && LoadQuadObj(ctrlPath, ctrl)) && !(isPly && LoadQuadLayer(ctrlPath, ctrl))) {
    TriData coarse;
    if (!LoadTri(ctrlPath, coarse)) return 1;
    ctrl = SplitTrianglesToQuads(coarse);
  }
  if (shuffleSeed > 0) {  // the same surface, another order: how much the fit depends on it
    std::mt19937 rng{static_cast<unsigned>(shuffleSeed)};
    std::shuffle(ctrl.F.begin(), ctrl.F.end(), rng);
    for (Quad& f : ctrl.F) std::rotate(f.begin(), f.begin() + rng() % 4, f.end());
  }
  std::printf("reference %s: %zu vertices, %zu triangles; control: %zu vertices, %zu quads; 2 cores\n",
              refPath.c_str(), ref.V.size(), ref.F.size(), ctrl.V.size(), ctrl.F.size());
  std::map<std::string, std::vector<double>> t;
  FitBakeResult last;
  p.normalMap = !outdir.empty();
  for (int r = 0; r < runs; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    EmbreeScene scene(ref);
    double tScene = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    last = FitAndBake(ctrl, ref, scene, p);
    if (!last.error.empty()) { std::fprintf(stderr, "error: %s\n", last.error.c_str()); return 1; }
    t["scene"].push_back(tScene);
    for (const auto& s : last.times) t[s.first].push_back(s.second);
    t["total"].push_back(last.totalSeconds + tScene);
  }
  const auto& m = last.metrics;
  std::printf("\nTable 1 | patches | irreg. | unp. %% | RMS L ‰ | RMS D ‰ | max L ‰ | max D ‰ | tiles (samples)\n");
  const int rMin = last.atlas.tileR.empty() ? 0 : *std::min_element(last.atlas.tileR.begin(), last.atlas.tileR.end());
  std::printf("        | %7d | %6d | %6.2f | %7.3f | %7.4f | %7.3f | %7.4f | %d..%d (%lld)\n", last.fit.patches,
              last.fit.irregularVertices, m.unprojectablePct, m.rmsLimitPermille, m.rmsDisplacedPermille,
              m.maxLimitPermille, m.maxDisplacedPermille, rMin, last.atlas.R, last.atlas.Samples());
  std::printf("\nTable 2 (median of %d runs, seconds) |", runs);
  const char* order[] = {"scene", "fit", "tessellate", "bake", "metrics", "total"};
  for (const char* k : order) std::printf(" %s %.3f |", k, Median(t[k]));
  std::printf(" peak memory %.1f MB\n", last.peakMemoryMb);
  std::printf("fit detail: samples %d (k %d..%d), iterations %d, RMS per iteration:", last.fit.samples,
              last.fit.minKUsed, last.fit.maxKUsed, last.fit.iterations);
  for (double e : last.fit.rmsPerIteration) std::printf(" %.3g", e);
  if (!last.fit.dataRmsPerIteration.empty()) {
    std::printf("\n  reference->limit RMS per iteration:");
    for (double e : last.fit.dataRmsPerIteration) std::printf(" %.3g", e);
    std::printf("\n  kept iterate %d (%s)", last.fit.keptIteration,
                p.fit.keepLowestDataRms ? "lowest reference->limit RMS" : "lowest objective");
  }
  std::printf("\n  displaced, area-weighted: reference -> displaced RMS %.4f, displaced -> reference RMS %.4f max %.4f permille",
              m.rmsDisplacedAreaPermille, m.rmsDisplacedToRefPermille, m.maxDisplacedToRefPermille);
  std::printf("\n  folded triangles: displaced layer %d of %zu, limit tessellation %d", m.displacedFolds,
              last.displaced.mesh.F.size(), m.limitFolds);
  if (last.displacementFit.fitted)
    std::printf("\n  displacement fit: %d round(s), reference->displaced RMS %.4g -> %.4g (unquantized)",
                last.displacementFit.iterations, last.displacementFit.rmsBefore, last.displacementFit.rmsAfter);
  std::printf(" (setup %.3f, factor %.3f, project %.3f, solve %.3f s)\n", last.fit.secondsSetup,
              last.fit.secondsFactor, last.fit.secondsProject, last.fit.secondsSolve);
  if (!outdir.empty()) {
    std::vector<std::string> errs = {
        WriteQuadObj(outdir + "/control.obj", last.fit.control, last.atlas.wedgeUV, "displacement.png"),
        WritePlyWithQuality(outdir + "/limit.ply", last.limit.mesh, &last.limit.quality),
        WritePlyWithQuality(outdir + "/displaced.ply", last.displaced.mesh, &last.displaced.quality),
        WritePngGray16(outdir + "/displacement.png", last.atlas.width, last.atlas.height, last.atlas.q16),
        WritePngRgb8(outdir + "/normal.png", last.atlas.width, last.atlas.height, last.atlas.normalRGB),
        WriteAtlasJson(outdir + "/displacement.json", last.atlas, "displacement.png", "normal.png"),
        WriteReportJson(outdir + "/report.json", last)};
    for (const auto& e : errs)
      if (!e.empty()) std::fprintf(stderr, "write error: %s\n", e.c_str());
    std::printf("outputs written to %s\n", outdir.c_str());
  }
  return 0;
}
