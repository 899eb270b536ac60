// libFuzzer target (issue 16: "every input a user can load: a valid result or a clear error,
// never a crash, hang or silent garbage"). The input bytes are decoded into a small vcg layer
// (vcgext::TMesh) as a corrupt or odd file could leave it: coordinates NaN / Inf / huge / tiny /
// duplicated, face corners repeated, on deleted vertices or past the vertex array, faux-edge
// flags, deleted faces. It then runs the mesh-facing entry points and checks what their headers
// promise (an error, or a result that satisfies the documented invariants):
//   ImportTriangles -> PrepareWorkingCopy -> TriToQuad on the working copy -> ComputeFitmaps
//   (the vcg entry point, or the array entry point on the raw import, which has no preconditions).
// Sizes are bounded (<= 64 vertices, <= 96 faces) so one input runs in milliseconds.
// Built only with -DFITMAP_FUZZ=ON (clang); scripts/fuzz.sh builds and runs it. A broken promise
// aborts with a message on stderr, which libFuzzer reports like a crash (with the input saved).
//
// Input layout (missing bytes read as 0):
//   [0] vertex count % 65   [1] face count % 97   [2] flags (kFlag*)   [3] coordinate scale 2^(b%241-120)
//   [4] deleted-vertex mask (vertices 0..7; with kFlagDeleted only)
//   vertices: 3 bytes each (kFlagRawCoords: 3 raw little-endian floats): byte < 0xF8 -> b-124 on the
//             grid, 0xF8.. -> NaN, +Inf, -Inf, FLT_MAX, -FLT_MAX, denormal, -0, 1e-30 (unscaled)
//   faces: 4 bytes each: 3 corners (b < 0xFC -> b % vertex count; 0xFC.. -> 0..3 past the last
//          vertex) and flags (bits 0-2 faux edges, bit 3 deleted face)
//   Fitmaps parameters: 8 bytes (see DecodeParams)
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <vector>

#include "vcg_ext/core/embree_scene.h"
#include "vcg_ext/core/indexed_mesh.h"
#include "vcg_ext/core/input_prep.h"
#include "vcg_ext/core/mesh_types.h"
#include "vcg_ext/fitmaps/fitmaps.h"
#include "vcg_ext/quad/quad_mesh.h"
#include "vcg_ext/quad/scan_artifacts.h"
#include "vcg_ext/quad/tri_to_quad.h"

namespace {

using vcgext::TMesh;
using vcgext::TriData;

constexpr int kMaxVertices = 64, kMaxFaces = 96, kPastEnd = 4;
// The issues this fuzzer found are fixed; their reproducers stay in tests/fuzz/regressions and
// are replayed by the FuzzMesh.Replay test: Embree's abort on rays beyond 1.8e18 (huge
// coordinates are now an input error, kMaxCoordinate) and vcglib's quadric collapse on
// coincident vertices (raw_working_resolution_coincident_vertices).
enum : uint8_t {
  kFlagAllowPolygonal = 1,  // ImportTriangles(allowPolygonal)
  kFlagKeepDegenerate = 2,  // ImportTriangles(keepDegenerate)
  kFlagRawCoords = 4,       // coordinates as raw float bits
  kFlagFitmaps = 8,         // run ComputeFitmaps
  kFlagFitmapsRaw = 16,     // ... through the array entry point on the raw import
  kFlagDeleted = 32,        // a deleted-vertex mask byte follows the header
  kFlagFarAway = 64,        // coordinates offset by 1e6 (float precision warning)
  kFlagReference = 128,     // FitmapParams::Mode::Reference
};

struct Reader {
  const uint8_t* p;
  size_t n;
  uint8_t U8() {
    if (n == 0) return 0;
    --n;
    return *p++;
  }
  float F32() {
    uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) bits |= uint32_t(U8()) << (8 * k);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }
};

// A broken promise: message on stderr, then abort (libFuzzer saves the input).
#define REQUIRE(cond, ...)                                             \
  do {                                                                 \
    if (!(cond)) {                                                     \
      std::fprintf(stderr, "fuzz_mesh: %s:%d: %s: ", __FILE__, __LINE__, #cond); \
      std::fprintf(stderr, __VA_ARGS__);                               \
      std::fprintf(stderr, "\n");                                      \
      std::abort();                                                    \
    }                                                                  \
  } while (0)

float Coordinate(uint8_t b, double scale, double offset) {
  static const float kSpecial[8] = {std::numeric_limits<float>::quiet_NaN(),
                                    std::numeric_limits<float>::infinity(),
                                    -std::numeric_limits<float>::infinity(),
                                    FLT_MAX, -FLT_MAX, 1e-45f, -0.0f, 1e-30f};
  if (b >= 0xF8) return kSpecial[b - 0xF8];
  return float((int(b) - 124) * scale + offset);
}

// Decodes the layer; returns the flags byte. Face corners past the vertex array point into
// reserved capacity (what a truncated file can leave: ImportTriangles must reject them unread).
uint8_t DecodeMesh(Reader& in, TMesh& m) {
  const int nV = in.U8() % (kMaxVertices + 1);
  const int nF = in.U8() % (kMaxFaces + 1);
  const uint8_t flags = in.U8();
  const double scale = std::ldexp(1.0, int(in.U8() % 241) - 120);
  const uint8_t deletedMask = (flags & kFlagDeleted) ? in.U8() : 0;
  const double offset = (flags & kFlagFarAway) ? 1e6 : 0.0;
  m.vert.reserve(nV + kPastEnd);
  if (nV > 0) vcg::tri::Allocator<TMesh>::AddVertices(m, nV);
  for (int i = 0; i < nV; ++i) {
    auto& P = m.vert[i].P();
    for (int k = 0; k < 3; ++k)
      P[k] = (flags & kFlagRawCoords) ? in.F32() : Coordinate(in.U8(), scale, offset);
  }
  if (nV == 0) return flags;  // ImportTriangles stops at "empty layer"; a face needs a vertex array
  TMesh::VertexPointer base = m.vert.data();
  vcg::tri::Allocator<TMesh>::AddFaces(m, nF);
  for (int f = 0; f < nF; ++f) {
    for (int k = 0; k < 3; ++k) {
      const uint8_t b = in.U8();
      m.face[f].V(k) = b < 0xFC ? base + b % nV : base + nV + (b - 0xFC);
    }
    const uint8_t ff = in.U8();
    for (int k = 0; k < 3; ++k)
      if (ff & (1 << k)) m.face[f].SetF(k);
    if (ff & 8) vcg::tri::Allocator<TMesh>::DeleteFace(m, m.face[f]);
  }
  for (int i = 0; i < std::min(nV, 8); ++i)
    if (deletedMask & (1 << i)) vcg::tri::Allocator<TMesh>::DeleteVertex(m, m.vert[i]);
  return flags;
}

vcgext::FitmapParams DecodeParams(Reader& in, uint8_t flags, int nV) {
  vcgext::FitmapParams p;
  p.mode = (flags & kFlagReference) ? vcgext::FitmapParams::Mode::Reference : vcgext::FitmapParams::Mode::Fast;
  p.numRadii = 1 + in.U8() % 9;
  p.tauPercent = in.U8() * (100.0 / 255.0);
  p.maxRadiusPercent = 1 + in.U8() % 100;
  const uint8_t wf = in.U8();
  p.workingFaces = wf < 128 ? 0 : 2 + wf % 64;  // small working resolutions: the decimation path
  const uint8_t bits = in.U8();
  p.fastFlipEstimator = (bits & 1) ? vcgext::FitmapParams::FlipEstimator::ForwardSelf
                                   : vcgext::FitmapParams::FlipEstimator::Coverage;
  p.fastSLevel = (bits >> 1) % 3;
  p.keepPerRadius = (bits & 8) != 0;
  p.minFitPoints = 1 + (bits >> 4);
  p.fastPointsPerFit = 4 + in.U8() % 60;
  p.seed = in.U8();
  const int subset = in.U8() % 4;  // a vertex subset (index nV: out of range, an error)
  for (int i = 0; i < subset; ++i) p.vertices.push_back(in.U8() % (nV + 1));
  return p;
}

// ImportTriangles' promise: either an error, or faces on existing vertices with finite coordinates.
void CheckImport(const vcgext::ImportReport& rep, const TriData& t, bool keepDegenerate) {
  if (!rep.error.empty()) return;
  REQUIRE(!t.F.empty(), "no faces without an error");
  for (const auto& v : t.V) REQUIRE(v.allFinite(), "non-finite vertex without an error");
  for (const auto& f : t.F) {
    for (int k = 0; k < 3; ++k) REQUIRE(f[k] >= 0 && f[k] < int(t.V.size()), "corner %d out of range", f[k]);
    if (!keepDegenerate) REQUIRE(f[0] != f[1] && f[1] != f[2] && f[0] != f[2], "degenerate face kept");
  }
}

// PrepareWorkingCopy's promise (input_prep.h): referenced vertices only, no degenerate or repeated
// faces, manifold (every vertex fan one disk or half-disk: non-manifold vertices split into copies
// at their position, the triangles on edges of three or more separated), consistently oriented,
// consistent maps.
void CheckWorkingCopy(const vcgext::WorkingCopy& w, int liveVertices) {
  REQUIRE(w.error.rfind("internal error", 0) != 0, "%s", w.error.c_str());  // the separation of edges failed
  if (!w.error.empty()) return;
  const TriData& m = w.mesh;
  const int n = int(m.V.size());
  REQUIRE(!m.F.empty(), "empty working copy without an error");
  REQUIRE(int(w.liveToMesh.size()) == liveVertices, "liveToMesh has %zu entries for %d live vertices",
          w.liveToMesh.size(), liveVertices);
  REQUIRE(int(w.meshToLive.size()) == n, "meshToLive size %zu != %d", w.meshToLive.size(), n);
  int copies = 0;  // vertices the split of non-manifold vertices made: their layer vertex maps to another
  for (int j = 0; j < n; ++j) {
    const int l = w.meshToLive[j];
    REQUIRE(l >= 0 && l < liveVertices, "meshToLive[%d] = %d out of range", j, l);
    if (w.liveToMesh[l] != j) {
      ++copies;
      REQUIRE(w.liveToMesh[l] >= 0 && m.V[w.liveToMesh[l]] == m.V[j],
              "meshToLive[%d] = %d does not map back, nor to a copy at its position", j, l);
    }
    REQUIRE(m.V[j].allFinite(), "non-finite working vertex %d", j);
  }
  REQUIRE(copies >= w.splitVertices && (copies > 0) == (w.splitVertices > 0), "%d copies for %d split vertices",
          copies, w.splitVertices);
  for (int l : w.liveToMesh) REQUIRE(l >= -1 && l < n, "liveToMesh entry %d out of range", l);
  std::vector<char> used(n, 0);
  std::set<std::pair<int, int>> directed;
  std::set<std::array<int, 3>> faces;
  std::vector<std::vector<std::pair<int, int>>> link(n);  // per vertex: its opposite edges
  for (const auto& f : m.F) {
    for (int k = 0; k < 3; ++k) REQUIRE(f[k] >= 0 && f[k] < n, "working corner %d out of range", f[k]);
    REQUIRE(f[0] != f[1] && f[1] != f[2] && f[0] != f[2], "degenerate working face");
    std::array<int, 3> s = f;
    std::sort(s.begin(), s.end());
    REQUIRE(faces.insert(s).second, "repeated working face");
    for (int k = 0; k < 3; ++k) {
      used[f[k]] = 1;
      REQUIRE(directed.insert({f[k], f[(k + 1) % 3]}).second,
              "directed edge %d->%d twice (non-manifold or inconsistently oriented)", f[k], f[(k + 1) % 3]);
      link[f[k]].push_back({f[(k + 1) % 3], f[(k + 2) % 3]});
    }
  }
  for (int j = 0; j < n; ++j) {
    REQUIRE(used[j], "unreferenced working vertex %d", j);
    // the link of a manifold vertex is one path or one cycle: connected
    std::map<int, int> parent;
    std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
    for (auto [a, b] : link[j]) {
      if (!parent.count(a)) parent[a] = a;
      if (!parent.count(b)) parent[b] = b;
      parent[find(a)] = find(b);
    }
    std::set<int> roots;
    for (auto& kv : parent) roots.insert(find(kv.first));
    REQUIRE(roots.size() == 1, "vertex %d: %zu separate sheets (non-manifold vertex)", j, roots.size());
  }
}

// TriToQuad's promise (tri_to_quad.h): valid pure quads on a manifold, oriented input.
void CheckQuads(const vcgext::quad::TriToQuadResult& r, const TriData& t) {
  REQUIRE(r.error.empty(), "TriToQuad failed on a valid working copy: %s", r.error.c_str());
  REQUIRE(r.quads.V.size() >= t.V.size(), "quad vertices lost");
  for (const auto& q : r.quads.F)
    for (int k = 0; k < 4; ++k)
      REQUIRE(q[k] >= 0 && q[k] < int(r.quads.V.size()), "quad corner %d out of range", q[k]);
  const std::string check = vcgext::quad::QuadMesh(r.quads.V, r.quads.F).Check();
  REQUIRE(check.empty(), "TriToQuad result invalid (path %s): %s", vcgext::quad::ToString(r.path), check.c_str());
}

// ComputeFitmaps' promise (fitmaps.h): an error, or finite values, one per vertex.
void CheckFitmaps(const vcgext::FitmapResult& r, size_t nV) {
  if (!r.error.empty()) return;
  REQUIRE(r.S.size() == nV && r.M.size() == nV, "S/M sizes %zu/%zu for %zu vertices", r.S.size(), r.M.size(), nV);
  for (size_t i = 0; i < nV; ++i)
    REQUIRE(std::isfinite(r.S[i]) && std::isfinite(r.M[i]), "vertex %zu: S %g M %g", i, r.S[i], r.M[i]);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Reader in{data, size};
  TMesh m;
  const uint8_t flags = DecodeMesh(in, m);
  int live = 0;
  for (const auto& v : m.vert) live += v.IsD() ? 0 : 1;

  TriData raw;
  const bool keepDegenerate = flags & kFlagKeepDegenerate;
  const vcgext::ImportReport rep = vcgext::ImportTriangles(m, raw, flags & kFlagAllowPolygonal, keepDegenerate);
  CheckImport(rep, raw, keepDegenerate);

  const vcgext::WorkingCopy w = vcgext::PrepareWorkingCopy(m);
  CheckWorkingCopy(w, live);
  if (w.error.empty()) CheckQuads(vcgext::quad::TriToQuad(w.mesh), w.mesh);

  if (flags & kFlagFitmaps) {
    if (flags & kFlagFitmapsRaw) {
      // The array entry point has no preconditions (non-manifold, degenerate faces, unreferenced
      // vertices are handled): run it on the raw import with degenerate faces kept.
      TriData all;
      if (vcgext::ImportTriangles(m, all, true, true).error.empty()) {
        const vcgext::FitmapParams p = DecodeParams(in, flags, int(all.V.size()));
        vcgext::EmbreeScene scene(all);
        CheckFitmaps(vcgext::ComputeFitmaps(all, scene, p), all.V.size());
        // the second-sheet measures on the same raw import (degenerate faces kept)
        const vcgext::SecondSheets d = vcgext::FindSecondSheets(all, scene);
        for (const vcgext::SheetShare& s : {d.doubled, d.thin})
          REQUIRE(s.areaPercent >= 0 && s.areaPercent <= 100 && s.medianDistance >= 0 && std::isfinite(s.medianDistance),
                  "second sheet: %g %% at %g", s.areaPercent, s.medianDistance);
      }
    } else {
      const vcgext::FitmapParams p = DecodeParams(in, flags, int(w.mesh.V.size()));
      CheckFitmaps(vcgext::ComputeFitmaps(m, p), w.mesh.V.size());
    }
  }
  // The attributes the vcg entry point added (FitmapS / FitmapM) belong to the caller: vcglib
  // 2020.09's ~TriMesh() does not free them (see tests/lsan.supp).
  m.ClearAttributes();
  return 0;
}
