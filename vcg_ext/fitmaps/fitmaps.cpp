// S- and M-Fitmaps (Panozzo et al. 2011, §3.1.2–3.1.3). Design and decisions: docs/fitmaps.md.
#include "vcg_ext/fitmaps/fitmaps.h"

#include "vcg_ext/core/decimate.h"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>

#include "vcg_ext/core/progress.h"
#include "vcg_ext/fitmaps/fitmaps_internal.h"

namespace vcgext {

using namespace fitmaps_internal;  // NOLINT (source file only)

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// One level of the vertex hierarchy of Fast mode (level 0 = the mesh itself).
struct Level {
  Adjacency adj;              ///< level graph
  std::vector<Vec3> X;        ///< positions (each a mesh vertex: the cluster seed)
  std::vector<double> W;      ///< number of mesh vertices the point stands for
  std::vector<int> fineIdx;   ///< mesh vertex of each level point
  std::vector<int> ofFine;    ///< mesh vertex -> level point (its cluster)
  Adjacency faces;            ///< level point -> mesh faces of its cluster
  std::vector<double> faceCum;  ///< cumulative face area within each cluster (aligned with faces.idx)
  std::vector<double> area;   ///< cluster area
  double areaPerPoint = 0;    ///< |M| / #points
  int index = 0;              ///< position in the hierarchy
};

/// Per-evaluation output, one slot per radius.
struct RadiusValues {
  std::vector<double> E, phi;
  std::vector<char> eOk, phiOk;
  void Init(int h) {
    E.assign(h, 0.0);
    phi.assign(h, 0.0);
    eOk.assign(h, 0);
    phiOk.assign(h, 0);
  }
};

/// Everything shared (read-only) by the per-vertex evaluations.
struct Context {
  const TriData* m = nullptr;       ///< the mesh with vertices in Morton order
  const std::vector<int>* orig = nullptr;  ///< vertex of m -> caller's vertex index
  const EmbreeScene* scene = nullptr;
  const FitmapParams* p = nullptr;
  std::vector<double> radii;
  std::vector<Vec3> normals;       ///< unit, or zero where even the fallback failed
  std::vector<double> faceArea;
  Adjacency vf;                    ///< vertex -> faces (Reference mode)
  double totalArea = 0;
  double tau = 0;                  ///< tau as a fraction
};

/// Per-thread scratch.
struct Scratch {
  std::vector<GatherScratch> perLevel;  ///< traversal scratch, one per hierarchy level
  std::vector<std::pair<int, double>> gathered;
  std::vector<Vec3> local;            ///< gathered points in the frame
  std::vector<double> cum;            ///< cumulative cluster areas along `gathered`
  std::vector<std::pair<double, int>> faces;  ///< (key, face) for Reference mode
  std::vector<unsigned> faceStamp, hitStamp;
  unsigned stamp = 0;
};

double Clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

/// RMS residual of `g` over the first n points (weighted), the paper's E(r_i) with the 1/n
/// moved under the root (see docs/fitmaps.md).
double Rms(const Cubic& g, const std::vector<Vec3>& P, const std::vector<double>* W,
           const std::vector<std::pair<int, double>>& gathered, size_t n) {
  double s = 0, sw = 0;
  for (size_t k = 0; k < n; ++k) {
    const double w = W ? (*W)[gathered[k].first] : 1.0;
    const double d = g.Eval(P[k][0], P[k][1]) - P[k][2];
    s += w * d * d;
    sw += w;
  }
  return sw > 0 ? std::sqrt(s / sw) : 0.0;
}

/// Whether the mesh point x (world) is the first hit of some normal line of the cubic, i.e.
/// lies in the image of the paper's projection: closest point on the cubic graph, then no other
/// surface on the line closer than x in either direction (and not farther than r).
bool InverseHit(const Context& ctx, const Frame& fr, const Cubic& g, const Vec3& xw, double r) {
  const Vec3 x = fr.Local(xw);
  double u, v;
  if (!ClosestPointOnCubic(g, x, 2.0 * r, u, v)) return false;
  const Vec3 P(u, v, g.Eval(u, v));
  const Vec3 N = g.Normal(u, v);
  const double s = (x - P).dot(N);
  if (std::abs(s) > r) return false;
  const double tol = 1e-3 * ctx.radii[0] + 1e-4 * std::abs(s);
  const double tfar = std::abs(s) - tol;
  if (tfar <= 0) return true;
  const Vec3 org = fr.World(P);
  const Vec3 dir = fr.WorldDir(s >= 0 ? N : Vec3(-N));
  if (ctx.scene->Intersect(org, dir, 0.0, tfar).valid) return false;
  if (ctx.scene->Intersect(org, -dir, 0.0, tfar).valid) return false;
  return true;
}

/// Uniform random point of triangle f.
Vec3 SampleTriangle(const TriData& m, int f, Rng& rng) {
  double a = rng.Uniform(), b = rng.Uniform();
  if (a + b > 1) { a = 1 - a; b = 1 - b; }
  const auto& t = m.F[f];
  return m.V[t[0]] + a * (m.V[t[1]] - m.V[t[0]]) + b * (m.V[t[2]] - m.V[t[0]]);
}

/// What one evaluation computes.
struct EvalSpec {
  int start = 0;        ///< level point the traversal starts from
  int vertex = 0;       ///< mesh vertex: origin, normal and random stream of the tangent frame
  bool doS = true, doM = true;
  bool literal = false;        ///< Reference mode M (forward rays from the paper's samples)
  bool stopMAtFailure = true;  ///< skip M for radii after the first failing one
};

// The fixed inputs of one evaluation: shared context, level, traversal keys and tangent frame.
struct Site {
  const Context& ctx;
  const Level& lv;
  const GatherScratch& gs;  ///< traversal keys of the level points (distance keys)
  const Frame& fr;
};

// Gathers the level points within rMax of e.start (a ball for one radius, else minimax keys).
GatherScratch& GatherLevelPoints(const Level& lv, const EvalSpec& e, int iBegin, int iEnd, double rMax,
                                 const Vec3& origin, Scratch& s) {
  if (s.perLevel.size() <= size_t(lv.index)) s.perLevel.resize(lv.index + 1);
  GatherScratch& gs = s.perLevel[lv.index];
  if (iEnd - iBegin == 1)
    GatherBall(lv.adj, lv.X, e.start, rMax, gs, s.gathered, &origin);
  else
    GatherMinimax(lv.adj, lv.X, e.start, rMax, gs, s.gathered, size_t(-1), &origin);
  return gs;
}

// Expresses the gathered level points in the tangent frame (s.local).
void ToLocalFrame(const Frame& fr, const Level& lv, Scratch& s) {
  s.local.resize(s.gathered.size());
  for (size_t k = 0; k < s.gathered.size(); ++k) s.local[k] = fr.Local(lv.X[s.gathered[k].first]);
}

// Reference mode: the faces within rMax keyed by their farthest corner, sorted (s.faces).
void CollectKeyedFaces(const Context& ctx, const GatherScratch& gs, double rMax, Scratch& s) {
  // A face belongs to B_i when all three corners do, so B_i's faces are a prefix.
  const TriData& m = *ctx.m;
  if (s.faceStamp.size() != m.F.size()) {
    s.faceStamp.assign(m.F.size(), 0);
    s.hitStamp.assign(m.F.size(), 0);
    s.stamp = 0;
  }
  ++s.stamp;
  s.faces.clear();
  for (const auto& [v, k] : s.gathered) {
    for (const int* it = ctx.vf.Begin(v); it != ctx.vf.End(v); ++it) {
      const int f = *it;
      if (s.faceStamp[f] == s.stamp) continue;
      s.faceStamp[f] = s.stamp;
      double fk = 0;
      for (int c : m.F[f]) fk = std::max(fk, gs.key[c]);
      if (fk <= rMax) s.faces.emplace_back(fk, f);
    }
  }
  std::sort(s.faces.begin(), s.faces.end());
}

// Fast mode: prefix sums of the cluster areas along `gathered` (s.cum).
void CumulateClusterAreas(const Level& lv, Scratch& s) {
  s.cum.resize(s.gathered.size() + 1);
  s.cum[0] = 0;
  for (size_t k = 0; k < s.gathered.size(); ++k) s.cum[k + 1] = s.cum[k] + lv.area[s.gathered[k].first];
}

// Adds the gathered points within radius r (from index nIn on) to the cubic fit.
void AddPointsWithin(double r, const std::vector<double>* W, const Scratch& s, CubicAccumulator& acc, size_t& nIn) {
  while (nIn < s.gathered.size() && s.gathered[nIn].second <= r) {
    const Vec3& l = s.local[nIn];
    acc.Add(l[0], l[1], l[2], W ? (*W)[s.gathered[nIn].first] : 1.0);
    ++nIn;
  }
}

// Reference mode: samples on a face of area a, perArea * a with randomised rounding, at least one.
int ReferenceSampleCount(double perArea, double a, Rng& rng) {
  const double want = perArea * a;
  int cnt = int(std::floor(want));
  if (rng.Uniform() < want - cnt) ++cnt;
  return std::max(cnt, 1);
}

// Reference mode: casts the forward rays from the cubic over the first nFaces faces; stamps hits.
unsigned StampReferenceHits(const Site& st, const Cubic& g, double r, size_t nFaces, Rng& rng, Scratch& s) {
  // The paper's sample count 4 n_M |B| / |M| (twice the vertex density), spread over the
  // faces in proportion to their area with randomised rounding and at least one sample
  // per non-degenerate face (else a plane would leave e^-2 = 13.5% of its faces un-hit).
  const Context& ctx = st.ctx;
  const TriData& m = *ctx.m;
  const double perArea = ctx.p->referenceSampleFactor * double(m.V.size()) / ctx.totalArea;
  ++s.stamp;
  const unsigned hitMark = s.stamp;
  for (size_t k = 0; k < nFaces; ++k) {
    const int f = s.faces[k].second;
    const double a = ctx.faceArea[f];
    if (a <= 0) continue;
    const int cnt = ReferenceSampleCount(perArea, a, rng);
    for (int j = 0; j < cnt; ++j) {
      const Vec3 x = st.fr.Local(SampleTriangle(m, f, rng));
      const Vec3 P(x[0], x[1], g.Eval(x[0], x[1]));
      const Vec3 N = g.Normal(x[0], x[1]);
      // Both directions along the normal line, nearest hit, at most r away.
      auto h = ctx.scene->IntersectLine(st.fr.World(P), st.fr.WorldDir(N), r);
      if (h.valid) s.hitStamp[h.face] = hitMark;
    }
  }
  return hitMark;
}

// Reference mode: the area of B_r's faces (total) and of those no forward ray hits (unhit).
void ReferenceUnhitArea(const Site& st, const Cubic& g, double r, size_t& nFaces, Rng& rng, Scratch& s,
                        double& unhit, double& total) {
  const Context& ctx = st.ctx;
  while (nFaces < s.faces.size() && s.faces[nFaces].first <= r) ++nFaces;
  for (size_t k = 0; k < nFaces; ++k) total += ctx.faceArea[s.faces[k].second];
  if (!(total > 0)) return;
  const unsigned hitMark = StampReferenceHits(st, g, r, nFaces, rng, s);
  for (size_t k = 0; k < nFaces; ++k) {
    const int f = s.faces[k].second;
    if (s.hitStamp[f] != hitMark) unhit += ctx.faceArea[f];
  }
}

// Fast mode: one area-uniform face of the neighbourhood of radius r (4 tries), or -1.
int SampleNeighbourhoodFace(const Site& st, const Scratch& s, size_t nIn, double total, double r, Rng& rng) {
  // Cluster, then face, then point; faces with a corner outside the neighbourhood (its cluster
  // not reached within r) are rejected, so the neighbourhood's faces are those the Reference
  // mode uses.
  const Level& lv = st.lv;
  const TriData& m = *st.ctx.m;
  int face = -1;
  for (int tries = 0; tries < 4 && face < 0; ++tries) {
    const double a = rng.Uniform() * total;
    size_t k = size_t(std::upper_bound(s.cum.begin(), s.cum.begin() + nIn + 1, a) - s.cum.begin());
    k = std::min(std::max<size_t>(k, 1), nIn) - 1;
    const int c = s.gathered[k].first;
    const int o = lv.faces.offs[c], e = lv.faces.offs[c + 1];
    if (o == e) continue;
    const double b = rng.Uniform() * lv.faceCum[e - 1];
    int fi = int(std::upper_bound(lv.faceCum.begin() + o, lv.faceCum.begin() + e, b) - lv.faceCum.begin());
    fi = std::min(fi, e - 1);
    const int f = lv.faces.idx[fi];
    bool inside = true;
    for (int corner : m.F[f]) inside = inside && st.gs.key[lv.ofFine[corner]] <= r;
    if (inside) face = f;
  }
  return face;
}

// Whether a ray's landing point lies on the border of `face` (1e-4 r_0; float rounding).
bool LandsOnFace(const Context& ctx, int face, const Vec3& point) {
  const auto& t = ctx.m->F[face];
  const Vec3 c = ClosestPointOnTriangle(point, ctx.m->V[t[0]], ctx.m->V[t[1]], ctx.m->V[t[2]]);
  return (c - point).norm() <= 1e-4 * ctx.radii[0];
}

// Fast mode, ForwardSelf: whether the normal line from the cubic above xw first hits `face`.
bool ForwardSelfHit(const Site& st, const Cubic& g, const Vec3& xw, int face, double r) {
  const Context& ctx = st.ctx;
  const Vec3 x = st.fr.Local(xw);
  const Vec3 P(x[0], x[1], g.Eval(x[0], x[1]));
  // nearest hit on the normal line within r, either direction (as IntersectLine),
  // casting first towards x: that hit is usually close, so the second ray is short
  Vec3 N = g.Normal(x[0], x[1]);
  if ((x - P).dot(N) < 0) N = -N;
  const Vec3 org = st.fr.World(P), dir = st.fr.WorldDir(N);
  auto h = ctx.scene->Intersect(org, dir, 0.0, r);
  auto hb = ctx.scene->Intersect(org, -dir, 0.0, h.valid ? h.t : r);
  if (hb.valid) h = hb;
  // the face itself, or a landing point on its border (a neighbour reported for a ray
  // through a shared edge, float rounding)
  return h.valid && (h.face == face || LandsOnFace(ctx, face, h.point));
}

// Fast mode: the share of the sampled neighbourhood points (of valid samples) that are not hit.
double FastUnhitShare(const Site& st, const Cubic& g, double r, size_t nIn, double total, Rng& rng,
                      const Scratch& s) {
  const FitmapParams& p = *st.ctx.p;
  const int K = std::max(1, p.fastFlipSamples);
  int miss = 0, valid = 0;
  for (int j = 0; j < K; ++j) {
    const int face = SampleNeighbourhoodFace(st, s, nIn, total, r, rng);
    if (face < 0) continue;
    ++valid;
    const Vec3 xw = SampleTriangle(*st.ctx.m, face, rng);
    bool hit;
    if (p.fastFlipEstimator == FitmapParams::FlipEstimator::ForwardSelf)
      hit = ForwardSelfHit(st, g, xw, face, r);
    else
      hit = InverseHit(st.ctx, st.fr, g, xw, r);
    if (!hit) ++miss;
  }
  return valid ? double(miss) / valid : 0.0;
}

// The flipped (un-hit) share of the neighbourhood of radius r for the cubic g, in [0, 1].
double FlippedShare(const Site& st, const EvalSpec& e, const Cubic& g, int i, size_t nIn, size_t& nFaces,
                    Scratch& s) {
  const Context& ctx = st.ctx;
  const double r = ctx.radii[i];
  Rng rng(ctx.p->seed, uint64_t((*ctx.orig)[e.vertex]), uint64_t(i));
  double unhit = 0, total = 0;
  if (e.literal) {
    ReferenceUnhitArea(st, g, r, nFaces, rng, s, unhit, total);
  } else {
    total = s.cum[nIn];
    if (total > 0) {
      unhit = FastUnhitShare(st, g, r, nIn, total, rng, s);
      total = 1;
    }
  }
  return total > 0 ? Clamp01(unhit / total) : 0.0;
}

// Fits the cubic at radii [iBegin, iEnd) (growing point set) and measures E (S) and phi (M).
void FitRadii(const Site& st, const EvalSpec& e, int iBegin, int iEnd, Scratch& s, RadiusValues& out) {
  const Context& ctx = st.ctx;
  const std::vector<double>* W = e.literal ? nullptr : &st.lv.W;
  CubicAccumulator acc;
  size_t nIn = 0, nFaces = 0;
  bool mFailed = false;
  for (int i = iBegin; i < iEnd; ++i) {
    const double r = ctx.radii[i];
    AddPointsWithin(r, W, s, acc, nIn);
    Cubic g;
    if (!acc.Solve(r, g)) continue;
    // S: radii with too few points are skipped.
    if (e.doS && acc.Count() >= ctx.p->minFitPoints) {
      out.E[i] = Rms(g, s.local, W, s.gathered, nIn);
      out.eOk[i] = 1;
    }
    // M (radius 0 never matters: F_M >= r_0 by definition).
    if (i == 0 || mFailed || !e.doM) continue;
    out.phi[i] = FlippedShare(st, e, g, i, nIn, nFaces, s);
    out.phiOk[i] = 1;
    if (e.stopMAtFailure && !(out.phi[i] < ctx.tau)) mFailed = true;
  }
}

/// Evaluates radii [iBegin, iEnd) for the frame of mesh vertex `e.vertex`, gathering the points
/// of level `lv` (level 0 = the mesh). Writes out.E/eOk (doS) and out.phi/phiOk (doM).
void Evaluate(const Context& ctx, const Level& lv, const EvalSpec& e, int iBegin, int iEnd, Scratch& s,
              RadiusValues& out) {
  const Vec3 n = ctx.normals[e.vertex];
  if (n.squaredNorm() == 0 || iBegin >= iEnd) return;
  const double rMax = ctx.radii[iEnd - 1];
  const Vec3 origin = ctx.m->V[e.vertex];
  const GatherScratch& gs = GatherLevelPoints(lv, e, iBegin, iEnd, rMax, origin, s);
  const Frame fr = Frame::Make(origin, n);
  ToLocalFrame(fr, lv, s);
  if (e.literal && e.doM)
    CollectKeyedFaces(ctx, gs, rMax, s);
  else if (e.doM)
    CumulateClusterAreas(lv, s);
  FitRadii(Site{ctx, lv, gs, fr}, e, iBegin, iEnd, s, out);
}

/// Area-weighted normals; where they vanish (unreferenced vertex, faces cancelling at a
/// non-manifold vertex), the PCA normal of the 30 nearest vertices of the connected
/// neighbourhood; zero if that is undefined too (a single isolated vertex).
std::vector<Vec3> RobustNormals(const TriData& m, const Adjacency& vv, double rMax, int& fallbacks) {
  std::vector<Vec3> N = VertexNormals(m);
  std::vector<int> bad;
  for (size_t i = 0; i < N.size(); ++i)
    if (N[i].squaredNorm() == 0 && vv.Count(int(i)) > 0) bad.push_back(int(i));
  fallbacks = int(bad.size());
#pragma omp parallel
  {
    GatherScratch gs;
    std::vector<std::pair<int, double>> got;
#pragma omp for schedule(dynamic, 16)
    for (long b = 0; b < long(bad.size()); ++b) {
      const int i = bad[b];
      GatherMinimax(vv, m.V, i, rMax, gs, got, 30);
      if (got.size() < 2) continue;
      Vec3 c = Vec3::Zero();
      for (auto& [q, k] : got) c += m.V[q];
      c /= double(got.size());
      Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
      for (auto& [q, k] : got) C += (m.V[q] - c) * (m.V[q] - c).transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
      Vec3 n = es.eigenvectors().col(0);
      if (n.allFinite() && n.norm() > 0.5) N[i] = n.normalized();
    }
  }
  return N;
}

/// Level 0 of the hierarchy: the mesh; faces belong to the cluster of their first corner.
Level MakeFineLevel(const TriData& m, const Adjacency& vv, double totalArea) {
  Level lv;
  const int n = int(m.V.size());
  lv.adj = vv;
  lv.X = m.V;
  lv.W.assign(n, 1.0);
  lv.fineIdx.resize(n);
  lv.ofFine.resize(n);
  for (int i = 0; i < n; ++i) lv.fineIdx[i] = lv.ofFine[i] = i;
  lv.areaPerPoint = totalArea / std::max(1, n);
  return lv;
}

/// Cluster -> faces lists with cumulative areas (face f belongs to the cluster of F[f][0]).
void BuildClusterFaces(const TriData& m, const std::vector<double>& faceArea, Level& lv) {
  const int nc = int(lv.X.size());
  lv.faces.offs.assign(nc + 1, 0);
  for (const auto& f : m.F) ++lv.faces.offs[lv.ofFine[f[0]] + 1];
  for (int c = 0; c < nc; ++c) lv.faces.offs[c + 1] += lv.faces.offs[c];
  lv.faces.idx.resize(m.F.size());
  std::vector<int> fill(lv.faces.offs.begin(), lv.faces.offs.end() - 1);
  for (size_t f = 0; f < m.F.size(); ++f) lv.faces.idx[fill[lv.ofFine[m.F[f][0]]]++] = int(f);
  lv.faceCum.resize(m.F.size());
  lv.area.assign(nc, 0.0);
  for (int c = 0; c < nc; ++c) {
    double acc = 0;
    for (int k = lv.faces.offs[c]; k < lv.faces.offs[c + 1]; ++k) {
      acc += faceArea[lv.faces.idx[k]];
      lv.faceCum[k] = acc;
    }
    lv.area[c] = acc;
  }
}

/// Next coarser level: seeds greedily covering the level within `cover` (connected traversal,
/// so clusters never join separate components), every point assigned to its graph-nearest seed
/// (multi-source Dijkstra on edge lengths), clusters adjacent when any members are.
Level Coarsen(const Level& f, double cover) {
  const int n = int(f.X.size());
  std::vector<char> covered(n, 0);
  std::vector<int> seeds;
  GatherScratch gs;
  std::vector<std::pair<int, double>> got;
  for (int i = 0; i < n; ++i) {
    if (covered[i]) continue;
    seeds.push_back(i);
    GatherMinimax(f.adj, f.X, i, cover, gs, got);
    for (auto& [q, k] : got) covered[q] = 1;
  }
  std::vector<int> label(n, -1);
  std::vector<double> dist(n, kInf);
  std::vector<std::pair<double, int>> heap;
  auto cmp = std::greater<std::pair<double, int>>();
  for (int s = 0; s < int(seeds.size()); ++s) {
    dist[seeds[s]] = 0;
    label[seeds[s]] = s;
    heap.emplace_back(0.0, seeds[s]);
  }
  std::make_heap(heap.begin(), heap.end(), cmp);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), cmp);
    auto [d, q] = heap.back();
    heap.pop_back();
    if (d > dist[q]) continue;
    for (const int* it = f.adj.Begin(q); it != f.adj.End(q); ++it) {
      const double nd = d + (f.X[*it] - f.X[q]).norm();
      if (nd < dist[*it]) {
        dist[*it] = nd;
        label[*it] = label[q];
        heap.emplace_back(nd, *it);
        std::push_heap(heap.begin(), heap.end(), cmp);
      }
    }
  }
  Level c;
  const int nc = int(seeds.size());
  c.X.resize(nc);
  c.fineIdx.resize(nc);
  c.W.assign(nc, 0.0);
  for (int s = 0; s < nc; ++s) {
    c.X[s] = f.X[seeds[s]];
    c.fineIdx[s] = f.fineIdx[seeds[s]];
  }
  for (int i = 0; i < n; ++i) c.W[label[i]] += f.W[i];
  std::vector<std::vector<int>> nb(nc);
  for (int i = 0; i < n; ++i)
    for (const int* it = f.adj.Begin(i); it != f.adj.End(i); ++it)
      if (label[*it] != label[i]) nb[label[i]].push_back(label[*it]);
  c.adj.offs.assign(nc + 1, 0);
  for (int s = 0; s < nc; ++s) {
    auto& l = nb[s];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    c.adj.offs[s + 1] = c.adj.offs[s] + int(l.size());
  }
  for (auto& l : nb) c.adj.idx.insert(c.adj.idx.end(), l.begin(), l.end());
  c.ofFine.resize(f.ofFine.size());
  for (size_t v = 0; v < f.ofFine.size(); ++v) c.ofFine[v] = label[f.ofFine[v]];
  return c;
}

/// a^{1/4} of the least-squares fit E = a r^4 (closed form a = sum E r^4 / sum r^8), computed
/// with radii relative to r_h to avoid overflow. Returns 0 when no radius was usable.
double SFromE(const std::vector<double>& radii, const RadiusValues& rv, bool& ok) {
  const double rh = radii.back();
  double num = 0, den = 0;
  ok = false;
  for (size_t i = 0; i < radii.size(); ++i) {
    if (!rv.eOk[i]) continue;
    const double q = radii[i] / rh, q4 = q * q * q * q;
    num += rv.E[i] * q4;
    den += q4 * q4;
    ok = true;
  }
  if (!ok || !(den > 0)) return 0.0;
  const double a = std::max(0.0, num / den) / (rh * rh * rh * rh);  // unit length^-3
  const double s = std::pow(a, 0.25);
  return std::isfinite(s) ? s : 0.0;
}

void Keep(const FitmapParams& p, const RadiusValues& rv, int v, FitmapResult& res) {
  if (!p.keepPerRadius) return;
  const size_t H = rv.E.size();
  for (size_t i = 0; i < H; ++i) {
    res.perRadiusE[v * H + i] = rv.eOk[i] ? rv.E[i] : -1.0;
    res.perRadiusFlipped[v * H + i] = rv.phiOk[i] ? rv.phi[i] : -1.0;
  }
}

/// F_M: the largest r_i such that r_1..r_i all have a flipped share below tau; at least r_0.
double MFromPhi(const Context& ctx, const RadiusValues& rv) {
  double M = ctx.radii[0];
  for (size_t i = 1; i < ctx.radii.size(); ++i) {
    if (!rv.phiOk[i] || !(rv.phi[i] < ctx.tau)) break;
    M = ctx.radii[i];
  }
  return M;
}

}  // namespace

namespace {
// Fitmaps of a dense mesh from its working resolution M': computed on M', then interpolated at
// each vertex's closest point on M'. Unreferenced vertices get S = 0, M = r_0 as usual.
FitmapResult FitmapsFromWorkingResolution(const TriData& input, const FitmapParams& p, vcg::CallBackPos* cb) {
  const auto t0 = std::chrono::steady_clock::now();
  WorkingResolutionParams wp;
  wp.maxFaces = p.workingFaces;
  DecimateResult d = WorkingResolution(input, wp, cb);
  FitmapResult res;
  EmbreeScene coarseScene(d.mesh);
  if (!coarseScene.Ok()) { res.error = "ray-casting scene of the working resolution: " + coarseScene.Error(); return res; }
  FitmapParams q = p;
  q.workingFaces = 0;
  FitmapResult c = ComputeFitmaps(d.mesh, coarseScene, q, cb);
  if (!c.error.empty()) return c;
  const auto t1 = std::chrono::steady_clock::now();
  const int n = int(input.V.size());
  res.S.assign(n, 0.0);
  res.M.assign(n, c.radii.empty() ? 0.0 : c.radii.front());
  res.computed.assign(n, 0);
  std::vector<char> used(n, 0);
  for (const auto& f : input.F)
    for (int v : f) used[v] = 1;
#pragma omp parallel
  {
    int hint = -1;  // the previous vertex's face (ClosestPoint's hint: neighbouring vertices)
#pragma omp for schedule(dynamic, 4096)
    for (int i = 0; i < n; ++i) {
      if (!used[i]) continue;
      EmbreeScene::Hit h = coarseScene.ClosestPoint(input.V[i], std::numeric_limits<double>::infinity(), hint);
      if (!h.valid) continue;
      hint = h.face;
      const Tri& t = d.mesh.F[h.face];
      const double w0 = 1.0 - h.u - h.v;
      res.S[i] = w0 * c.S[t[0]] + h.u * c.S[t[1]] + h.v * c.S[t[2]];
      res.M[i] = w0 * c.M[t[0]] + h.u * c.M[t[1]] + h.v * c.M[t[2]];
      res.computed[i] = 1;
    }
  }
  for (char u : used) res.unreferenced += u ? 0 : 1;
  res.radii = c.radii;
  res.fallbackNormals = c.fallbackNormals;
  res.noFit = c.noFit;
  res.levels = c.levels;
  res.workingFaces = int(d.mesh.F.size());
  res.secondsDecimate = d.seconds;
  if (d.zeroAreaFlips > 0)
    res.notes.push_back(std::to_string(d.zeroAreaFlips) +
                        " edge flips removed zero-area triangles from the decimated copy (the layer is unchanged)");
  if (d.skippedDegenerate)
    res.warnings.push_back("zero-area triangles with coincident corners: computed on all " +
                           std::to_string(input.F.size()) +
                           " triangles instead of a decimated copy (slower; Filters > Cleaning and Repairing > "
                           "Remove Zero Area Faces avoids it)");
  res.secondsTransfer = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}
}  // namespace

namespace {

// ComputeFitmaps' argument checks, in order: the first problem, or empty.
std::string CheckFitmapInputs(const TriData& input, const EmbreeScene& scene, const FitmapParams& p) {
  const int nV = int(input.V.size());
  if (nV == 0) return "the mesh is empty (no vertices)";
  if (input.F.empty()) return "the mesh has no faces (point cloud): a triangle mesh is needed";
  for (size_t i = 0; i < input.V.size(); ++i)
    if (!input.V[i].allFinite()) return "vertex " + std::to_string(i) + " has NaN or infinite coordinates";
  for (size_t i = 0; i < input.V.size(); ++i)
    if (input.V[i].cwiseAbs().maxCoeff() > kMaxCoordinate) {
      return "vertex " + std::to_string(i) + " has a coordinate beyond 1e17, more than the ray caster can represent: scale the mesh down";
    }
  int badIdx = 0;
  for (const auto& f : input.F)
    for (int c : f) badIdx += (c < 0 || c >= nV) ? 1 : 0;
  if (badIdx) return std::to_string(badIdx) + " face corners refer to no vertex (index out of range)";
  if (!(p.tauPercent >= 0 && p.tauPercent <= 100)) return "tau must be in [0, 100] percent";
  if (p.numRadii < 1 || p.numRadii > 64) return "the number of radii must be in [1, 64]";
  if (!(p.maxRadiusPercent > 0 && p.maxRadiusPercent <= 100)) {
    return "the largest radius must be in (0, 100] percent of the bbox diagonal";
  }
  if (!(p.minRadiusPercent >= 0 && p.minRadiusPercent <= p.maxRadiusPercent)) {
    return "the smallest radius must be in [0, largest radius] percent of the bbox diagonal";
  }
  if (!(p.referenceSampleFactor > 0 && p.referenceSampleFactor <= 1e4)) {
    return "referenceSampleFactor must be in (0, 10000]";
  }
  if (p.minFitPoints < 1) return "minFitPoints must be at least 1";
  for (int v : p.vertices)
    if (v < 0 || v >= nV) return "vertex subset: index " + std::to_string(v) + " is out of range";
  if (!scene.Ok()) return "ray-casting scene: " + scene.Error();
  if (scene.Mesh().V.size() != input.V.size() || scene.Mesh().F.size() != input.F.size()) {
    return "the ray-casting scene was not built on this mesh";
  }
  if (p.workingFaces < 0) return "the working resolution must be >= 0 triangles";
  return {};
}

// Vertices in Morton (Z-curve) order, so that the traversals touch nearby memory: order[k] is
// the caller's vertex of rank k, rank its inverse (the results are mapped back; faces keep their
// order, so the Embree scene stays valid).
void MortonOrder(const std::vector<Vec3>& V, std::vector<int>& order, std::vector<int>& rank) {
  const int nV = int(V.size());
  order.resize(nV);
  rank.resize(nV);
  Vec3 lo = V[0], hi = V[0];
  for (const auto& q : V) { lo = lo.cwiseMin(q); hi = hi.cwiseMax(q); }
  const double ext = std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<std::pair<uint64_t, int>> code(nV);
  auto spread = [](uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  };
  for (int i = 0; i < nV; ++i) {
    const Vec3 t = (V[i] - lo) / ext * 2097151.0;
    code[i] = {spread(uint64_t(t[0])) | spread(uint64_t(t[1])) << 1 | spread(uint64_t(t[2])) << 2, i};
  }
  std::sort(code.begin(), code.end());
  for (int k = 0; k < nV; ++k) { order[k] = code[k].second; rank[code[k].second] = k; }
}

// S and M of vertex v (and its per-radius values when kept) from its radius values; false when
// the S fit failed.
bool StoreVertex(const Context& ctx, const RadiusValues& rv, int v, FitmapResult& res) {
  bool ok;
  res.S[v] = SFromE(ctx.radii, rv, ok);
  res.M[v] = MFromPhi(ctx, rv);
  Keep(*ctx.p, rv, v, res);
  return ok;
}

// Reference mode (paper §3.1 literally): every vertex of `todo`, all radii, on the mesh itself.
// Returns the vertices whose S fit failed.
int ReferenceValues(Context& ctx, const Level& fine, const std::vector<int>& todo, FitmapResult& res,
                    Progress& prog) {
  const TriData& m = *ctx.m;
  const int nV = int(m.V.size()), H = int(ctx.radii.size());
  std::atomic<long> done{0};
  int noFit = 0;
  ctx.vf = VertexFaceAdjacency(m.F, nV);
#pragma omp parallel reduction(+ : noFit)
  {
    Scratch s;
    RadiusValues rv;
#pragma omp for schedule(dynamic, 4)
    for (long k = 0; k < long(todo.size()); ++k) {
      const int v = todo[k];
      rv.Init(H);
      EvalSpec e;
      e.start = e.vertex = v;
      e.literal = true;
      Evaluate(ctx, fine, e, 0, H, s, rv);
      if (!StoreVertex(ctx, rv, v, res)) ++noFit;
      ++done;
      if (omp_get_thread_num() == 0) prog(100.0 * done / todo.size(), "Fitmaps (reference)");
    }
  }
  return noFit;
}

// Fast mode's plan: the hierarchy of levels (level 0 = the mesh), for each radius the coarsest
// level whose neighbourhood of that radius still holds about fastPointsPerFit points, and which
// radii get their S fitted per vertex (on level levelS) instead of interpolated.
struct FastPlan {
  std::vector<Level> levels;
  std::vector<int> levelOf, levelS;
  std::vector<char> perVertexS;
};
FastPlan PlanFastLevels(const Context& ctx, Level fine, double r0, double rh) {
  const TriData& m = *ctx.m;
  const FitmapParams& p = *ctx.p;
  const int H = int(ctx.radii.size());
  FastPlan plan;
  std::vector<Level>& levels = plan.levels;
  levels.push_back(std::move(fine));
  BuildClusterFaces(m, ctx.faceArea, levels[0]);
  const double target = std::max(16, p.fastPointsPerFit);
  std::vector<int>& levelOf = plan.levelOf;
  levelOf.assign(H, 0);
  for (int i = 0; i < H; ++i) {
    const double r = ctx.radii[i];
    int l = 0;
    while (true) {
      if (int(levels.size()) <= l + 1) {
        const Level& f = levels.back();
        if (f.X.size() < 64 || levels.size() >= 16) break;
        const double cover = r0 * std::pow(2.0, 0.5 * double(levels.size()));
        Level c = Coarsen(f, cover);
        c.areaPerPoint = ctx.totalArea / double(c.X.size());
        c.index = int(levels.size());
        BuildClusterFaces(m, ctx.faceArea, c);
        levels.push_back(std::move(c));
      }
      const Level& nx = levels[l + 1];
      if (M_PI * r * r / nx.areaPerPoint >= target) ++l; else break;
    }
    levelOf[i] = l;
  }
  // E(r_i) enters a with weight (r_i/r_h)^4: radii below r_h/2.5 weigh < 2.6% each (and their
  // E is much smaller than E(r_h)), so they
  // are interpolated from the level points like the flipped shares; the larger ones are
  // fitted per vertex in the vertex's own frame (the frame matters most there).
  plan.perVertexS.assign(H, 0);
  plan.levelS.assign(H, 0);
  for (int i = 0; i < H; ++i) {
    if (levelOf[i] == 0 || ctx.radii[i] < rh / 2.5) continue;
    plan.perVertexS[i] = 1;
    // the per-vertex S fits use more points than the M estimates (fastPointsPerSFit)
    const double r = ctx.radii[i];
    int l = 0;
    while (l + 1 < int(levels.size()) &&
           M_PI * r * r / levels[l + 1].areaPerPoint >= std::max(16, p.fastPointsPerSFit))
      ++l;
    plan.levelS[i] = l;
  }
  return plan;
}

// Fast mode, coarse levels: every level point, all radii of that level (values[l][q]).
std::vector<std::vector<RadiusValues>> CoarseValues(const Context& ctx, const FastPlan& plan) {
  const int H = int(ctx.radii.size());
  std::vector<std::vector<RadiusValues>> coarse(plan.levels.size());
  for (size_t l = 1; l < plan.levels.size(); ++l) {
    int i0 = H, i1 = 0;
    for (int i = 0; i < H; ++i)
      if (plan.levelOf[i] == int(l)) { i0 = std::min(i0, i); i1 = std::max(i1, i + 1); }
    if (i0 >= i1) continue;
    const Level& lv = plan.levels[l];
    coarse[l].resize(lv.X.size());
#pragma omp parallel
    {
      Scratch s;
#pragma omp for schedule(dynamic, 8)
      for (long q = 0; q < long(lv.X.size()); ++q) {
        coarse[l][q].Init(H);
        EvalSpec e;
        e.start = int(q);
        e.vertex = lv.fineIdx[q];
        e.doS = true;  // used where S is not fitted per vertex (radii below r_h / 6)
        e.stopMAtFailure = false;
        Evaluate(ctx, lv, e, i0, i1, s, coarse[l][q]);
      }
    }
  }
  return coarse;
}

// Calls fn(cc, w) for the point cc of level lv that stands for fine vertex v (its cluster), then
// for each neighbour of it, with the interpolation weight w = exp(-d^2 / (2 * area per point)), d
// the distance from x (v's position) to the point.
template <class Fn>
void ForNearPoints(const Level& lv, int v, const Vec3& x, Fn&& fn) {
  const int c = lv.ofFine[v];
  const double inv = 1.0 / (2.0 * lv.areaPerPoint);
  auto take = [&](int cc) { fn(cc, std::exp(-(lv.X[cc] - x).squaredNorm() * inv)); };
  take(c);
  for (const int* it = lv.adj.Begin(c); it != lv.adj.End(c); ++it) take(*it);
}

// The large-radius S fits of fine vertex v in rv, interpolated from those at the points of level
// sLevel (sVals), for the radii fitted per vertex (FastPlan::perVertexS).
void InterpolateLargeS(const FastPlan& plan, int sLevel, const std::vector<RadiusValues>& sVals, int v,
                       const Vec3& x, RadiusValues& rv) {
  const Level& lv = plan.levels[sLevel];
  for (int i = 0; i < int(plan.perVertexS.size()); ++i) {
    if (!plan.perVertexS[i]) continue;
    double we = 0, se = 0;
    ForNearPoints(lv, v, x, [&](int cc, double w) {
      if (!sVals[cc].eOk[i]) return;
      we += w;
      se += w * sVals[cc].E[i];
    });
    if (we > 0) { rv.E[i] = se / we; rv.eOk[i] = 1; }
  }
}

// The coarse radii [i1fine, H) of fine vertex v in rv, interpolated from their levels' points
// (`coarse`): E where it is not fitted per vertex, phi when `needM`.
void InterpolateCoarse(const FastPlan& plan, const std::vector<std::vector<RadiusValues>>& coarse, int i1fine,
                       bool needM, int v, const Vec3& x, RadiusValues& rv) {
  for (int i = i1fine; i < int(plan.levelOf.size()); ++i) {
    const auto& vals = coarse[plan.levelOf[i]];
    double wp = 0, sp = 0, we = 0, se = 0;
    ForNearPoints(plan.levels[plan.levelOf[i]], v, x, [&](int cc, double w) {
      if (vals[cc].phiOk[i]) { wp += w; sp += w * vals[cc].phi[i]; }
      if (vals[cc].eOk[i]) { we += w; se += w * vals[cc].E[i]; }
    });
    if (we > 0 && !plan.perVertexS[i]) { rv.E[i] = se / we; rv.eOk[i] = 1; }
    if (wp > 0 && needM) { rv.phi[i] = sp / wp; rv.phiOk[i] = 1; }
  }
}

// The per-vertex S fits of the large radii (FastPlan::perVertexS) in the frame of fine vertex v,
// each run of radii on one level evaluated together.
void FitLargeS(const Context& ctx, const FastPlan& plan, int v, Scratch& s, RadiusValues& rv) {
  const int H = int(ctx.radii.size());
  EvalSpec ec;
  ec.vertex = v;
  ec.doM = false;
  for (int i = 0; i < H;) {
    if (!plan.perVertexS[i]) { ++i; continue; }
    int j = i;
    while (j < H && plan.perVertexS[j] && plan.levelS[j] == plan.levelS[i]) ++j;
    ec.start = plan.levels[plan.levelS[i]].ofFine[v];
    Evaluate(ctx, plan.levels[plan.levelS[i]], ec, i, j, s, rv);
    i = j;
  }
}

// Fast mode, per vertex of `todo`: the fine-level radii, the large-radius S fits (per vertex or
// interpolated from level sLevel's points) and the coarse radii interpolated from `coarse`.
// Returns the vertices whose S fit failed.
int FastValues(const Context& ctx, const FastPlan& plan, const std::vector<std::vector<RadiusValues>>& coarse,
               const std::vector<int>& todo, FitmapResult& res, Progress& prog,
               std::chrono::steady_clock::time_point t0) {
  const TriData& m = *ctx.m;
  const FitmapParams& p = *ctx.p;
  const int H = int(ctx.radii.size());
  std::atomic<long> done{0};
  int noFit = 0;
  // large-radius S fits in the frames of the points of level sLevel (0: every vertex)
  const int sLevel = std::clamp(p.fastSLevel, 0, int(plan.levels.size()) - 1);
  std::vector<RadiusValues> sVals;
  if (sLevel > 0) {
    const Level& lv = plan.levels[sLevel];
    sVals.resize(lv.X.size());
#pragma omp parallel
    {
      Scratch s;
#pragma omp for schedule(dynamic, 16)
      for (long q = 0; q < long(lv.X.size()); ++q) {
        sVals[q].Init(H);
        FitLargeS(ctx, plan, lv.fineIdx[q], s, sVals[q]);
      }
    }
  }
  prog(30, "Fitmaps: vertices", true);
  res.secondsCoarse = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // fine level per vertex + interpolation of the coarse radii
  int i1fine = 0;
  while (i1fine < H && plan.levelOf[i1fine] == 0) ++i1fine;
#pragma omp parallel reduction(+ : noFit)
  {
    Scratch s;
    RadiusValues rv;
#pragma omp for schedule(dynamic, 32)
    for (long k = 0; k < long(todo.size()); ++k) {
      const int v = todo[k];
      rv.Init(H);
      EvalSpec e;
      e.start = e.vertex = v;
      Evaluate(ctx, plan.levels[0], e, 0, i1fine, s, rv);
      if (sLevel == 0) FitLargeS(ctx, plan, v, s, rv);
      bool needM = true;
      for (int i = 1; i < i1fine; ++i)
        if (!(rv.phiOk[i] && rv.phi[i] < ctx.tau)) needM = false;
      if (ctx.normals[v].squaredNorm() > 0) {
        if (sLevel > 0) InterpolateLargeS(plan, sLevel, sVals, v, m.V[v], rv);
        InterpolateCoarse(plan, coarse, i1fine, needM, v, m.V[v], rv);
      }
      if (!StoreVertex(ctx, rv, v, res)) ++noFit;
      ++done;
      if (omp_get_thread_num() == 0) prog(30 + 70.0 * done / todo.size(), "Fitmaps");
    }
  }
  return noFit;
}

// The input with its vertices in Morton order (MortonOrder: order[k] is the input vertex at k,
// rank its inverse), the faces renumbered.
TriData MortonOrdered(const TriData& input, std::vector<int>& order, std::vector<int>& rank) {
  const int nV = int(input.V.size());
  MortonOrder(input.V, order, rank);
  TriData mm;
  mm.V.resize(nV);
  for (int k = 0; k < nV; ++k) mm.V[k] = input.V[order[k]];
  mm.F = input.F;
  for (auto& f : mm.F)
    for (int& c : f) c = rank[c];
  return mm;
}

// The vertices to compute (FitmapParams::vertices as Morton ranks, sorted and unique; every
// vertex when empty), with res's per-vertex arrays sized and set for them (M = r_0, the paper's
// grid; `unreferenced` counted from the adjacency vv).
std::vector<int> VerticesToCompute(const Context& ctx, const std::vector<int>& rank, const Adjacency& vv,
                                   FitmapResult& res) {
  const FitmapParams& p = *ctx.p;
  const int nV = int(ctx.m->V.size()), H = int(ctx.radii.size());
  std::vector<int> todo;
  for (int v : p.vertices) todo.push_back(rank[v]);
  std::sort(todo.begin(), todo.end());
  todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
  if (todo.empty()) {
    todo.resize(nV);
    for (int i = 0; i < nV; ++i) todo[i] = i;
  }
  res.S.assign(nV, 0.0);
  res.M.assign(nV, 0.0);
  res.computed.assign(nV, 0);
  for (int v : todo) {
    res.computed[v] = 1;
    res.M[v] = ctx.radii[0];  // r_0 on the paper's grid
  }
  if (p.keepPerRadius) {
    res.perRadiusE.assign(size_t(nV) * H, -1.0);
    res.perRadiusFlipped.assign(size_t(nV) * H, -1.0);
  }
  for (int v : todo) res.unreferenced += vv.Count(v) == 0 ? 1 : 0;
  return todo;
}

// res's per-vertex arrays back from Morton order to the caller's (order: MortonOrdered's).
void ToCallerOrder(const std::vector<int>& order, int H, FitmapResult& res) {
  const int nV = int(order.size());
  auto unpermute = [&](auto& vec, size_t stride) {
    if (vec.empty()) return;
    auto tmp = vec;
    for (int k = 0; k < nV; ++k)
      for (size_t j = 0; j < stride; ++j) vec[size_t(order[k]) * stride + j] = tmp[size_t(k) * stride + j];
  };
  unpermute(res.S, 1);
  unpermute(res.M, 1);
  unpermute(res.computed, 1);
  unpermute(res.perRadiusE, size_t(H));
  unpermute(res.perRadiusFlipped, size_t(H));
}

}  // namespace

std::vector<double> FitmapRadii(double r0, double rh, double diag, const FitmapParams& p) {
  std::vector<double> radii;
  if (p.minRadiusPercent > 0) {
    const double floor = std::max(r0, p.minRadiusPercent / 100.0 * diag) * (1 - 1e-9);
    for (double r = rh; r >= floor && radii.size() < 64; r /= kAnchoredRadiusRatio) radii.push_back(r);
    if (radii.empty()) radii.push_back(rh);
    std::reverse(radii.begin(), radii.end());
    return radii;
  }
  const int H = p.numRadii;
  for (int i = 0; i < H; ++i) radii.push_back(H == 1 ? r0 : r0 * std::pow(rh / r0, double(i) / double(H - 1)));
  return radii;
}

FitmapResult ComputeFitmaps(const TriData& input, const EmbreeScene& scene, const FitmapParams& p,
                            vcg::CallBackPos* cb) {
  const auto t0 = std::chrono::steady_clock::now();
  FitmapResult res;
  res.error = CheckFitmapInputs(input, scene, p);
  if (!res.error.empty()) return res;
  if (p.workingFaces > 0 && int(input.F.size()) > p.workingFaces && p.vertices.empty() &&
      p.mode == FitmapParams::Mode::Fast && !p.keepPerRadius) {
    return FitmapsFromWorkingResolution(input, p, cb);
  }

  // ---- vertices in Morton order (MortonOrder)
  const int nV = int(input.V.size());
  std::vector<int> order, rank;
  const TriData m = MortonOrdered(input, order, rank);

  // ---- radii: r_0 = average edge length, r_h = maxRadiusPercent of the diagonal (FitmapRadii)
  Context ctx;
  ctx.m = &m;
  ctx.orig = &order;
  ctx.scene = &scene;
  ctx.p = &p;
  ctx.tau = p.tauPercent / 100.0;
  const double r0 = AverageEdgeLength(m);
  const double diag = BBoxDiagonal(m.V);
  if (!(r0 > 0) || !std::isfinite(r0)) { res.error = "all edges have zero length"; return res; }
  const double rh = std::max(r0, p.maxRadiusPercent / 100.0 * diag);
  ctx.radii = FitmapRadii(r0, rh, diag, p);
  const int H = int(ctx.radii.size());
  res.radii = ctx.radii;

  Progress prog(cb);
  prog(0, "Fitmaps: preparing", true);
  ctx.faceArea.resize(m.F.size());
  for (size_t f = 0; f < m.F.size(); ++f) {
    const auto& t = m.F[f];
    ctx.faceArea[f] = 0.5 * (m.V[t[1]] - m.V[t[0]]).cross(m.V[t[2]] - m.V[t[0]]).norm();
    ctx.totalArea += ctx.faceArea[f];
  }
  if (!(ctx.totalArea > 0)) { res.error = "all faces have zero area"; return res; }
  const Adjacency vv = VertexVertexAdjacency(m.F, nV);
  ctx.normals = RobustNormals(m, vv, rh, res.fallbackNormals);

  // ---- which vertices
  const std::vector<int> todo = VerticesToCompute(ctx, rank, vv, res);

  Level fine = MakeFineLevel(m, vv, ctx.totalArea);
  if (p.mode == FitmapParams::Mode::Reference) {
    res.noFit = ReferenceValues(ctx, fine, todo, res, prog);
  } else {
    FastPlan plan = PlanFastLevels(ctx, std::move(fine), r0, rh);
    res.levels = int(plan.levels.size());
    res.secondsLevels = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (int i = 0; i < H; ++i) res.radiusLevel.push_back(plan.levelOf[i]);
    prog(5, "Fitmaps: coarse levels", true);
    const auto coarse = CoarseValues(ctx, plan);
    res.noFit = FastValues(ctx, plan, coarse, todo, res, prog, t0);
  }
  ToCallerOrder(order, H, res);  // back to the caller's vertex order
  prog(100, "Fitmaps: done", true);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace vcgext
