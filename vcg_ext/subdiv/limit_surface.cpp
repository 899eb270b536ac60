#include "vcg_ext/subdiv/limit_surface.h"
#include "vcg_ext/subdiv/osd_refiner.h"
#include "vcg_ext/core/union_find.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace vcgext {

namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;

struct LimitSurface::Impl {
  std::vector<osd::Bfr::Surface<double>> surfaces;  ///< one per base face, read-only after Build
  std::vector<int> cvOffs;                           ///< control-point indices of face f: cvIdx[cvOffs[f]..cvOffs[f+1])
  std::vector<int> cvIdx;
  int maxCV = 0;

  /// One Bfr surface per face of `refiner`, with its control-point indices; "" or an error that
  /// counts the faces with no limit surface and names the first.
  std::string InitSurfaces(const osd::Far::TopologyRefiner& refiner, const LimitSurfaceOptions& opt);

  /// The limit stencil of face f at (u,v), derivatives up to `order`, one control point at a
  /// time in increasing index order, duplicates merged (a small closed mesh can wrap a
  /// neighbourhood onto itself): visit(index, weights) with weights[0..nd) = P, Du, Dv, Duu,
  /// Duv, Dvv. No allocation for usual sizes. Stencil() stores what it visits, Evaluate() applies
  /// it; both see the same sums in the same order.
  template <class Visit>
  void VisitStencil(int f, double u, double v, int order, Visit&& visit) const {
    const auto& s = surfaces[f];
    const int n = s.GetNumControlPoints();
    const int nd = order == 0 ? 1 : order == 1 ? 3 : 6;
    double local[6 * 64];
    int localPerm[64];
    std::vector<double> heap;
    std::vector<int> heapPerm;
    double* w = local;
    int* perm = localPerm;
    if (n * nd > int(sizeof(local) / sizeof(double))) { heap.resize(size_t(n) * nd); w = heap.data(); }
    if (n > 64) { heapPerm.resize(n); perm = heapPerm.data(); }
    const double uv[2] = {u, v};
    if (order == 0) s.EvaluateStencil(uv, w);
    else if (order == 1) s.EvaluateStencil(uv, w, w + n, w + 2 * n);
    else s.EvaluateStencil(uv, w, w + n, w + 2 * n, w + 3 * n, w + 4 * n, w + 5 * n);
    const int* idx = cvIdx.data() + cvOffs[f];
    std::iota(perm, perm + n, 0);
    std::sort(perm, perm + n, [&](int a, int b) { return idx[a] < idx[b]; });
    for (int j = 0; j < n;) {
      const int id = idx[perm[j]];
      double acc[6];
      for (int d = 0; d < nd; ++d) acc[d] = w[d * n + perm[j]];
      for (++j; j < n && idx[perm[j]] == id; ++j)
        for (int d = 0; d < nd; ++d) acc[d] += w[d * n + perm[j]];
      visit(id, static_cast<const double*>(acc));
    }
  }
};

namespace {

inline std::uint64_t EdgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

}  // namespace

LimitSurface::LimitSurface(LimitSurface&&) noexcept = default;
LimitSurface& LimitSurface::operator=(LimitSurface&&) noexcept = default;
LimitSurface::~LimitSurface() = default;

LimitSurface::LimitSurface(int numVertices, const std::vector<int>& faceSizes, const std::vector<int>& faceVerts,
                           const LimitSurfaceOptions& opt)
    : opt_(opt) {
  Build(numVertices, faceSizes, faceVerts);
}

LimitSurface LimitSurface::FromQuads(const QuadData& q, LimitSurfaceOptions opt) {
  opt.scheme = SubdivScheme::CatmullClark;
  std::vector<int> sizes(q.F.size(), 4), verts;
  verts.reserve(q.F.size() * 4);
  for (const auto& f : q.F) verts.insert(verts.end(), f.begin(), f.end());
  LimitSurface s;
  s.opt_ = opt;
  s.Build(int(q.V.size()), sizes, verts);
  return s;
}

LimitSurface LimitSurface::FromTriangles(const TriData& t, LimitSurfaceOptions opt) {
  opt.scheme = SubdivScheme::Loop;
  std::vector<int> sizes(t.F.size(), 3), verts;
  verts.reserve(t.F.size() * 3);
  for (const auto& f : t.F) verts.insert(verts.end(), f.begin(), f.end());
  LimitSurface s;
  s.opt_ = opt;
  s.Build(int(t.V.size()), sizes, verts);
  return s;
}

namespace {

// Per undirected edge: how many face sides use it, the first two (face, corner) and the first
// side's start vertex.
struct EdgeInfo { int count = 0; int f0 = -1, k0 = -1, f1 = -1, k1 = -1; int a0 = -1; };
using EdgeInfoTable = std::unordered_map<std::uint64_t, EdgeInfo>;

// A mesh at all, face sizes (3 for Loop, else at least 3) and their sum against the index list.
std::string CheckFaceSizes(int nV, const std::vector<int>& sizes, const std::vector<int>& verts, bool loop) {
  if (nV <= 0) return "the control mesh has no vertices";
  if (sizes.empty()) return "the control mesh has no faces";
  size_t total = 0;
  int badSize = 0, firstBadSize = -1;
  for (size_t f = 0; f < sizes.size(); ++f) {
    bool bad = loop ? sizes[f] != 3 : sizes[f] < 3;
    if (bad) { if (firstBadSize < 0) firstBadSize = int(f); ++badSize; }
    total += size_t(std::max(sizes[f], 0));
  }
  if (badSize)
    return std::to_string(badSize) + " faces have an invalid size (" +
           (loop ? std::string("Loop needs triangles") : std::string("at least 3 corners")) + "; first: face " +
           std::to_string(firstBadSize) + " with " + std::to_string(sizes[firstBadSize]) + " corners)";
  if (total != verts.size())
    return "face sizes add up to " + std::to_string(total) + " corners but " + std::to_string(verts.size()) +
           " vertex indices were given";
  return {};
}

// Face corners: vertex indices in range, no vertex twice in a face.
std::string CheckFaceCorners(int nV, const std::vector<int>& sizes, const std::vector<int>& verts) {
  int badIdx = 0, firstBadIdx = -1, rep = 0, firstRep = -1;
  for (size_t f = 0, o = 0; f < sizes.size(); o += sizes[f], ++f) {
    for (int k = 0; k < sizes[f]; ++k) {
      int a = verts[o + k];
      if (a < 0 || a >= nV) { if (firstBadIdx < 0) firstBadIdx = int(f); ++badIdx; }
      for (int j = 0; j < k; ++j)
        if (verts[o + j] == a) { if (firstRep < 0) firstRep = int(f); ++rep; }
    }
  }
  if (badIdx)
    return std::to_string(badIdx) + " face corners reference a vertex out of range [0," + std::to_string(nV) +
           ") (first: face " + std::to_string(firstBadIdx) + ")";
  if (rep)
    return std::to_string(rep) + " faces repeat a vertex (first: face " + std::to_string(firstRep) + ")";
  return {};
}

// Edges: each directed edge at most once, each undirected edge in at most two faces. Fills
// `edges` (empty on entry).
std::string CollectEdges(const std::vector<int>& sizes, const std::vector<int>& verts, EdgeInfoTable& edges) {
  edges.reserve(verts.size());
  int nonMan = 0, flipped = 0;
  std::pair<int, int> firstNonMan{-1, -1}, firstFlip{-1, -1};
  for (size_t f = 0, o = 0; f < sizes.size(); o += sizes[f], ++f) {
    const int n = sizes[f];
    for (int k = 0; k < n; ++k) {
      int a = verts[o + k], b = verts[o + (k + 1) % n];
      EdgeInfo& e = edges[EdgeKey(a, b)];
      ++e.count;
      if (e.count == 1) { e.f0 = int(f); e.k0 = k; e.a0 = a; }
      else if (e.count == 2) {
        e.f1 = int(f); e.k1 = k;
        if (e.a0 == a) { if (firstFlip.first < 0) firstFlip = {a, b}; ++flipped; }
      } else if (e.count == 3) {
        if (firstNonMan.first < 0) firstNonMan = {a, b};
        ++nonMan;
      }
    }
  }
  if (nonMan)
    return std::to_string(nonMan) + " non-manifold edges (shared by more than two faces; first: vertices " +
           std::to_string(firstNonMan.first) + "-" + std::to_string(firstNonMan.second) + ")";
  if (flipped)
    return std::to_string(flipped) + " edges join faces of inconsistent orientation (first: vertices " +
           std::to_string(firstFlip.first) + "-" + std::to_string(firstFlip.second) + ")";
  return {};
}

// Crease edges are mesh edges, corner vertices are in range.
std::string CheckSharpFeatures(int nV, const LimitSurfaceOptions& opt, const EdgeInfoTable& edges) {
  for (const auto& c : opt.creaseEdges) {
    if (c.first < 0 || c.first >= nV || c.second < 0 || c.second >= nV || !edges.count(EdgeKey(c.first, c.second)))
      return "crease edge " + std::to_string(c.first) + "-" + std::to_string(c.second) + " is not an edge of the mesh";
  }
  for (int c : opt.cornerVertices)
    if (c < 0 || c >= nV) return "corner vertex " + std::to_string(c) + " is out of range";
  return {};
}

// Non-manifold vertices (several fans of faces meeting at one vertex): union the corners of a
// vertex across its interior edges, then count fans per vertex.
std::string CheckVertexFans(int nV, const std::vector<int>& sizes, const std::vector<int>& verts,
                            const EdgeInfoTable& edges) {
  std::vector<int> cornerOffs(sizes.size() + 1, 0);
  for (size_t f = 0; f < sizes.size(); ++f) cornerOffs[f + 1] = cornerOffs[f] + sizes[f];
  UnionFind uf(int(verts.size()));
  for (const auto& kv : edges) {
    const EdgeInfo& e = kv.second;
    if (e.count != 2) continue;
    int n0 = sizes[e.f0], n1 = sizes[e.f1];
    // e goes a->b in f0 (corners k0, k0+1) and b->a in f1 (corners k1, k1+1).
    uf.Unite(cornerOffs[e.f0] + e.k0, cornerOffs[e.f1] + (e.k1 + 1) % n1);
    uf.Unite(cornerOffs[e.f0] + (e.k0 + 1) % n0, cornerOffs[e.f1] + e.k1);
  }
  std::vector<int> root(nV, -1);
  int bowtie = 0, firstBowtie = -1;
  std::vector<char> counted(nV, 0);
  for (size_t c = 0; c < verts.size(); ++c) {
    int v = verts[c], r = uf.Find(int(c));
    if (root[v] < 0) root[v] = r;
    else if (root[v] != r && !counted[v]) {
      counted[v] = 1;
      ++bowtie;
      if (firstBowtie < 0) firstBowtie = v;
    }
  }
  if (bowtie)
    return std::to_string(bowtie) + " non-manifold vertices (several separate fans of faces; first: vertex " +
           std::to_string(firstBowtie) + ")";
  return {};
}

// Valences (into `valence`) and boundary flags (returned) of the vertices.
std::vector<char> CountValences(int nV, const EdgeInfoTable& edges, std::vector<int>& valence) {
  std::vector<char> boundary(nV, 0);
  valence.assign(nV, 0);
  for (const auto& kv : edges) {
    int a = int(kv.first >> 32), b = int(kv.first & 0xffffffffu);
    ++valence[a];
    ++valence[b];
    if (kv.second.count == 1) boundary[a] = boundary[b] = 1;
  }
  return boundary;
}

// Interior valence-2 vertices (doublets): OpenSubdiv 3.5.0's Bfr returns surfaces whose
// control-point indices are partly uninitialised around them (found with valgrind on a
// decimated + paired elephant; it crashed the fit). Refuse them with a clear message.
std::string CheckDoublets(int nV, const std::vector<int>& valence, const std::vector<char>& boundary) {
  int doublets = 0, firstDoublet = -1;
  for (int v = 0; v < nV; ++v)
    if (valence[v] == 2 && !boundary[v]) {
      if (firstDoublet < 0) firstDoublet = v;
      ++doublets;
    }
  if (doublets)
    return std::to_string(doublets) + " interior vertices have valence 2 (doublets; first: vertex " +
           std::to_string(firstDoublet) +
           "): remove them first (vcgext::RemoveDoublets merges the two faces round each); where those two faces "
           "share all their edges (a closed piece of two faces, what triangle pairing makes of a tetrahedron) "
           "nothing can be merged: delete such pieces (e.g. Filters > Cleaning and Repairing > Remove Isolated "
           "pieces (wrt Face Num.))";
  return {};
}

// Irregular vertices: valence other than the scheme's regular interior / boundary valence
// (isolated vertices do not count).
int CountIrregular(int nV, const std::vector<int>& valence, const std::vector<char>& boundary, bool loop) {
  int irregular = 0;
  const int regInterior = loop ? 6 : 4, regBoundary = loop ? 4 : 3;
  for (int v = 0; v < nV; ++v) {
    if (valence[v] == 0) continue;
    if (valence[v] != (boundary[v] ? regBoundary : regInterior)) ++irregular;
  }
  return irregular;
}

// A vertex above maxValence (> 0): an error that names it and the remeshing filter.
std::string CheckMaxValence(const std::vector<int>& valence, int maxValence, bool loop) {
  if (maxValence <= 0 || valence.empty()) return {};
  const auto it = std::max_element(valence.begin(), valence.end());
  if (*it <= maxValence) return {};
  return "vertex " + std::to_string(it - valence.begin()) + " has " + std::to_string(*it) + " edges (at most " +
         std::to_string(maxValence) +
         " are supported: the limit surface round such a vertex takes gigabytes); remesh the control mesh there "
         "first (e.g. Filters > Remeshing, Simplification and Reconstruction > Remeshing: Isotropic Explicit "
         "Remeshing" + std::string(loop ? ")" : ", then pair the triangles into quads)");
}

// A face of more sides than maxValence (> 0): Catmull-Clark's patch of an n-gon is that of a
// vertex of n edges (its face point after the first step), as costly to build (a 3 000-gon: 8
// minutes).
std::string CheckMaxFaceSize(const std::vector<int>& sizes, int maxValence) {
  if (maxValence <= 0 || sizes.empty()) return {};
  const auto it = std::max_element(sizes.begin(), sizes.end());
  if (*it <= maxValence) return {};
  return "face " + std::to_string(it - sizes.begin()) + " has " + std::to_string(*it) + " sides (at most " +
         std::to_string(maxValence) + " are supported: its limit patch is that of a vertex of as many edges); split it first";
}

}  // namespace

std::string LimitSurface::CheckTopology(int nV, const std::vector<int>& sizes, const std::vector<int>& verts,
                                        const LimitSurfaceOptions& opt) {
  LimitSurface s;
  s.opt_ = opt;
  return s.Validate(nV, sizes, verts);
}

std::string LimitSurface::Validate(int nV, const std::vector<int>& sizes, const std::vector<int>& verts) {
  const bool loop = opt_.scheme == SubdivScheme::Loop;
  std::string err = CheckFaceSizes(nV, sizes, verts, loop);
  if (err.empty()) err = CheckMaxFaceSize(sizes, opt_.maxValence);
  if (err.empty()) err = CheckFaceCorners(nV, sizes, verts);
  if (!err.empty()) return err;
  EdgeInfoTable edges;
  err = CollectEdges(sizes, verts, edges);
  if (err.empty()) err = CheckSharpFeatures(nV, opt_, edges);
  if (err.empty()) err = CheckVertexFans(nV, sizes, verts, edges);
  if (!err.empty()) return err;
  // Valences, boundary flags, irregular vertices.
  const std::vector<char> boundary = CountValences(nV, edges, valence_);
  err = CheckDoublets(nV, valence_, boundary);
  if (!err.empty()) return err;
  numIrregular_ = CountIrregular(nV, valence_, boundary, loop);
  return CheckMaxValence(valence_, opt_.maxValence, loop);
}

namespace subdiv_detail {

// OpenSubdiv's topology refiner of the control mesh, with the options' scheme, boundary rule and
// infinitely sharp crease edges and corners; null when OpenSubdiv rejects the topology.
std::unique_ptr<osd::Far::TopologyRefiner> CreateRefiner(int nV, const std::vector<int>& sizes,
                                                         const std::vector<int>& verts, const LimitSurfaceOptions& opt) {
  using Descriptor = osd::Far::TopologyDescriptor;
  Descriptor desc;
  desc.numVertices = nV;
  desc.numFaces = int(sizes.size());
  desc.numVertsPerFace = sizes.data();
  desc.vertIndicesPerFace = verts.data();
  std::vector<int> creasePairs;
  std::vector<float> creaseW, cornerW;
  for (const auto& c : opt.creaseEdges) { creasePairs.push_back(c.first); creasePairs.push_back(c.second); }
  creaseW.assign(opt.creaseEdges.size(), osd::Sdc::Crease::SHARPNESS_INFINITE);
  cornerW.assign(opt.cornerVertices.size(), osd::Sdc::Crease::SHARPNESS_INFINITE);
  desc.numCreases = int(opt.creaseEdges.size());
  desc.creaseVertexIndexPairs = creasePairs.data();
  desc.creaseWeights = creaseW.data();
  desc.numCorners = int(opt.cornerVertices.size());
  desc.cornerVertexIndices = opt.cornerVertices.data();
  desc.cornerWeights = cornerW.data();

  osd::Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(opt.sharpBoundaryCorners ? osd::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                                           : osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  sdc.SetFVarLinearInterpolation(osd::Sdc::Options::FVAR_LINEAR_ALL);
  const osd::Sdc::SchemeType type =
      opt.scheme == SubdivScheme::Loop ? osd::Sdc::SCHEME_LOOP : osd::Sdc::SCHEME_CATMARK;
  using Factory = osd::Far::TopologyRefinerFactory<Descriptor>;
  return std::unique_ptr<osd::Far::TopologyRefiner>(Factory::Create(desc, Factory::Options(type, sdc)));
}

}  // namespace subdiv_detail

std::string LimitSurface::Impl::InitSurfaces(const osd::Far::TopologyRefiner& refiner, const LimitSurfaceOptions& opt) {
  osd::Bfr::SurfaceFactory::Options fopt;
  fopt.SetApproxLevelSmooth(opt.approxLevelSmooth).SetApproxLevelSharp(opt.approxLevelSharp);
  osd::Bfr::RefinerSurfaceFactory<> factory(refiner, fopt);
  const int nF = refiner.GetLevel(0).GetNumFaces();
  surfaces.resize(nF);
  cvOffs.assign(nF + 1, 0);
  int noLimit = 0, firstNoLimit = -1;
  for (int f = 0; f < nF; ++f) {
    auto& s = surfaces[f];
    if (!factory.InitVertexSurface<double>(f, &s) || !s.IsValid()) {
      if (firstNoLimit < 0) firstNoLimit = f;
      ++noLimit;
      cvOffs[f + 1] = cvOffs[f];
      continue;
    }
    int n = s.GetNumControlPoints();
    maxCV = std::max(maxCV, n);
    cvIdx.resize(cvOffs[f] + n);
    s.GetControlPointIndices(cvIdx.data() + cvOffs[f]);
    cvOffs[f + 1] = cvOffs[f] + n;
  }
  if (noLimit == 0) return {};
  return std::to_string(noLimit) + " faces have no limit surface (first: face " + std::to_string(firstNoLimit) + ")";
}

void LimitSurface::Build(int nV, const std::vector<int>& sizes, const std::vector<int>& verts) {
  numVertices_ = std::max(nV, 0);
  faceOffs_.assign(1, 0);
  error_ = Validate(nV, sizes, verts);
  if (!error_.empty()) return;
  if (opt_.approxLevelSmooth < 1 || opt_.approxLevelSmooth > 10 || opt_.approxLevelSharp < 1 ||
      opt_.approxLevelSharp > 10) {
    error_ = "approxLevelSmooth / approxLevelSharp must be in 1..10";
    return;
  }
  faceVerts_ = verts;
  faceOffs_.resize(sizes.size() + 1);
  for (size_t f = 0; f < sizes.size(); ++f) faceOffs_[f + 1] = faceOffs_[f] + sizes[f];
  vertexCorner_.assign(nV, {-1, -1});
  for (size_t f = 0; f < sizes.size(); ++f)
    for (int k = 0; k < sizes[f]; ++k) {
      int v = verts[faceOffs_[f] + k];
      if (vertexCorner_[v].first < 0) vertexCorner_[v] = {int(f), k};
    }

  const std::unique_ptr<osd::Far::TopologyRefiner> refiner = subdiv_detail::CreateRefiner(nV, sizes, verts, opt_);
  if (!refiner) {
    error_ = "OpenSubdiv rejected the control mesh topology";
    return;
  }
  auto impl = std::make_unique<Impl>();
  error_ = impl->InitSurfaces(*refiner, opt_);
  if (error_.empty()) impl_ = std::move(impl);
}

int LimitSurface::NumPatchPoints(int face) const {
  if (!impl_ || face < 0 || face >= NumFaces()) return 0;
  return impl_->cvOffs[face + 1] - impl_->cvOffs[face];
}

bool LimitSurface::FaceIsRegular(int face) const {
  if (!impl_ || face < 0 || face >= NumFaces()) return false;
  return impl_->surfaces[face].IsRegular();
}

void LimitSurface::CornerUV(int face, int k, double& u, double& v) const {
  u = v = 0;
  if (!impl_ || face < 0 || face >= NumFaces()) return;
  double uv[2];
  impl_->surfaces[face].GetParameterization().GetVertexCoord(k, uv);
  u = uv[0];
  v = uv[1];
}

bool LimitSurface::Stencil(int face, double u, double v, LimitStencil& out, int order) const {
  out.index.clear();
  out.P.clear(); out.Du.clear(); out.Dv.clear(); out.Duu.clear(); out.Duv.clear(); out.Dvv.clear();
  if (!impl_ || face < 0 || face >= NumFaces() || order < 0 || order > 2) return false;
  const int nd = order == 0 ? 1 : order == 1 ? 3 : 6;
  std::vector<double>* arr[6] = {&out.P, &out.Du, &out.Dv, &out.Duu, &out.Duv, &out.Dvv};
  impl_->VisitStencil(face, u, v, order, [&](int id, const double* wt) {
    out.index.push_back(id);
    for (int d = 0; d < nd; ++d) arr[d]->push_back(wt[d]);
  });
  return true;
}

bool LimitSurface::Evaluate(int face, double u, double v, const std::vector<Vec3>& ctrl, Vec3* P, Vec3* Du,
                            Vec3* Dv, Vec3* Duu, Vec3* Duv, Vec3* Dvv) const {
  if (int(ctrl.size()) != numVertices_) return false;
  if (!impl_ || face < 0 || face >= NumFaces()) return false;
  const int order = (Duu || Duv || Dvv) ? 2 : (Du || Dv) ? 1 : 0;
  const int nd = order == 0 ? 1 : order == 1 ? 3 : 6;
  Vec3* out[6] = {P, Du, Dv, Duu, Duv, Dvv};
  for (int d = 0; d < nd; ++d)
    if (out[d]) out[d]->setZero();
  // the stencil applied as it comes (this runs per texel, tessellation vertex and fit sample):
  // the same sums as applying Stencil()'s output (tests/subdiv compare the two to the last bit)
  impl_->VisitStencil(face, u, v, order, [&](int id, const double* wt) {
    for (int d = 0; d < nd; ++d)
      if (out[d]) *out[d] += wt[d] * ctrl[id];
  });
  return true;
}

Eigen::SparseMatrix<double> LimitSurface::VertexLimitMatrix() const {
  Eigen::SparseMatrix<double> L;
  if (!Ok() || !impl_) return L;
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(size_t(numVertices_) * 16);
  LimitStencil st;
  for (int v = 0; v < numVertices_; ++v) {
    auto fc = vertexCorner_[v];
    if (fc.first < 0) { trip.emplace_back(v, v, 1.0); continue; }
    double u, w;
    CornerUV(fc.first, fc.second, u, w);
    Stencil(fc.first, u, w, st, 0);
    for (int i = 0; i < st.Size(); ++i)
      if (st.P[i] != 0.0) trip.emplace_back(v, st.index[i], st.P[i]);
  }
  L.resize(numVertices_, numVertices_);
  L.setFromTriplets(trip.begin(), trip.end());
  return L;
}

}  // namespace vcgext
