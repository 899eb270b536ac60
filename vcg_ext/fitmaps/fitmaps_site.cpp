/// \file fitmaps_site.cpp
/// One vertex's Fitmap evaluation (Panozzo et al. 2011, §3.1.2–3.1.3): the points of its
/// neighbourhood in its tangent frame, the cubic height field fitted at each radius, its RMS
/// residual E(r_i) (S-fitmap) and the share of the neighbourhood it cannot project onto
/// (M-fitmap), in Reference mode by the paper's forward rays, in Fast mode by sampled points.
#include "vcg_ext/fitmaps/fitmaps_eval.h"

#include "vcg_ext/core/embree_scene.h"

#include <algorithm>
#include <cmath>

namespace vcgext::fitmaps_internal {

namespace {

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

}  // namespace

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

}  // namespace vcgext::fitmaps_internal
