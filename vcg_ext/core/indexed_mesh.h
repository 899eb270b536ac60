#pragma once
/// \file indexed_mesh.h
/// Plain indexed triangle / quad arrays (double precision) that the algorithm cores work on,
/// plus the templated bridge from any vcglib triangle mesh (CMeshO in MeshLab, vcgext::TMesh in
/// tests). The bridge validates the input and says what is wrong instead of asserting.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace vcgext {

using Vec3 = Eigen::Vector3d;
using Tri = std::array<int, 3>;
using Quad = std::array<int, 4>;

/// A triangle mesh as arrays. `vcgIndex[i]` is the position of vertex i among the live
/// (non-deleted) vertices of the vcg mesh it came from, so results can be written back.
struct TriData {
  std::vector<Vec3> V;
  std::vector<Tri> F;
};

/// A pure-quad mesh as arrays (counter-clockwise corners).
struct QuadData {
  std::vector<Vec3> V;
  std::vector<Quad> F;
};

/// A polygonal mesh as arrays: each face a counter-clockwise loop of at least three vertices
/// (a control layer with triangles or n-gons among its quads, before SubdivideOnce).
struct PolyData {
  std::vector<Vec3> V;
  std::vector<std::vector<int>> F;
};

/// For each quad, the corner s (0 or 1) that starts a "free" diagonal s–(s+2): one that is not a
/// mesh edge and not the diagonal chosen for an earlier quad. Splitting every quad along its free
/// diagonal gives a manifold triangulation whose faux-edge pairing is unique (two quads may have
/// the same two opposite corners; splitting both along them would not). `blocked` (optional)
/// counts quads where neither diagonal is free (s = 0 then).
std::vector<int> FreeDiagonalStarts(const QuadData& q, int* blocked = nullptr);

/// `x` rounded to the nearest float, as MeshLab 2020.09 stores a coordinate. Through a volatile
/// float: Debian 12's g++ 12.2 at -O2 vectorizes a loop of double(float(x)) into the identity for
/// two of the three coordinates (SLP vectorizer; a 5-line reproducer gives 0.1 back unrounded),
/// which left a few vertices of fandisk.off unrounded.
inline double RoundedToFloat(double x) {
  volatile float f = float(x);
  return double(f);
}

/// Axis-aligned bounding box diagonal of a point set (0 for an empty set).
double BBoxDiagonal(const std::vector<Vec3>& V);
/// Largest |coordinate| of a point set (0 for an empty set): what float rounding scales with.
double LargestCoordinate(const std::vector<Vec3>& V);
/// Mean length of the mesh's edges, each undirected edge counted once.
double AverageEdgeLength(const TriData& m);
/// Total area of the triangles.
double TotalArea(const TriData& m);
/// Area-weighted vertex normals (unit; zero for unreferenced/degenerate vertices).
std::vector<Vec3> VertexNormals(const TriData& m);
/// Unit face normals (zero for degenerate faces).
std::vector<Vec3> FaceNormals(const TriData& m);

/// Compressed adjacency lists (CSR): neighbours of i are idx[offs[i] .. offs[i+1]).
struct Adjacency {
  std::vector<int> offs, idx;
  int Count(int i) const { return offs[i + 1] - offs[i]; }
  const int* Begin(int i) const { return idx.data() + offs[i]; }
  const int* End(int i) const { return idx.data() + offs[i + 1]; }
};
/// Vertex -> incident faces.
Adjacency VertexFaceAdjacency(const std::vector<Tri>& F, int nV);
/// Half-edges (a, b) of the faces whose twin (b, a) is in no face: the boundary of an oriented
/// manifold, in face order (face by face, sides 01, 12, 20). Linear time (VertexFaceAdjacency).
std::vector<std::pair<int, int>> BoundaryHalfEdges(const TriData& m);
/// The quads as triangles, each split along its 0-2 diagonal (q0 q1 q2, q0 q2 q3), in order.
TriData SplitQuads(const QuadData& q);
/// Vertex -> adjacent vertices (each once, through any incident face).
Adjacency VertexVertexAdjacency(const std::vector<Tri>& F, int nV);

/// Outcome of reading a vcg layer. `error` is empty on success.
struct ImportReport {
  std::string error;
  int deletedSkipped = 0;   ///< deleted vertices/faces that were ignored
  int degenerateFaces = 0;  ///< faces with repeated vertices (kept out of F)
  int unreferenced = 0;     ///< vertices used by no face (kept in V)
};

/// Largest coordinate magnitude the filters accept. Embree (all ray casting) rejects rays whose
/// origin or direction has a coordinate beyond FLT_LARGE = 1.844e18 (Debian's build aborts on
/// them: the fuzzer's known_embree_ray_origin_beyond_1.8e18); rays start on the surface and reach
/// a few bounding-box diagonals beyond it, so an order of magnitude is left.
constexpr double kMaxCoordinate = 1e17;

namespace import_detail {
/// What ImportVertices found: each vcg vertex's index in `out` (-1: deleted), and the vertices
/// with non-finite or too large coordinates (their count and the first one's index in `out`).
struct VertexScan {
  std::vector<int> remap;
  int nonFinite = 0, firstBad = -1, huge = 0, firstHuge = -1;
};
/// What ImportFaces found: faux edges, live faces, faces with a reference outside the vertices,
/// and which of `out`'s vertices a kept face uses.
struct FaceScan {
  int faux = 0, live = 0, badRef = 0;
  std::vector<char> used;
};

/// The live vertices of `m` appended to out.V.
template <class MeshType>
VertexScan ImportVertices(const MeshType& m, TriData& out, ImportReport& rep) {
  VertexScan s;
  s.remap.assign(m.vert.size(), -1);
  for (size_t i = 0; i < m.vert.size(); ++i) {
    if (m.vert[i].IsD()) { ++rep.deletedSkipped; continue; }
    const auto& p = m.vert[i].cP();
    Vec3 q{double(p[0]), double(p[1]), double(p[2])};
    if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2])) {
      if (s.firstBad < 0) s.firstBad = int(out.V.size());
      ++s.nonFinite;
    } else if (q.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      if (s.firstHuge < 0) s.firstHuge = int(out.V.size());
      ++s.huge;
    }
    s.remap[i] = int(out.V.size());
    out.V.push_back(q);
  }
  return s;
}

/// The live faces of `m` appended to out.F on the vertices `remap` gives (those repeating a
/// vertex only with `keepDegenerate`; counted in `rep`).
template <class MeshType>
FaceScan ImportFaces(const MeshType& m, const std::vector<int>& remap, bool keepDegenerate, TriData& out,
                     ImportReport& rep) {
  FaceScan s;
  s.used.assign(out.V.size(), 0);
  const auto* v0 = m.vert.empty() ? nullptr : &m.vert[0];
  for (const auto& f : m.face) {
    if (f.IsD()) { ++rep.deletedSkipped; continue; }
    ++s.live;
    for (int k = 0; k < 3; ++k) if (f.IsF(k)) ++s.faux;
    Tri t;
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const auto d = f.cV(k) - v0;  // a corrupt file can leave references outside the vertices
      t[k] = d >= 0 && d < std::ptrdiff_t(remap.size()) ? remap[size_t(d)] : -1;
      ok = ok && t[k] >= 0;
    }
    if (!ok) { ++s.badRef; continue; }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++rep.degenerateFaces;
      if (!keepDegenerate) continue;
    }
    for (int k = 0; k < 3; ++k) s.used[t[k]] = 1;
    out.F.push_back(t);
  }
  return s;
}

/// The error ImportTriangles gives for what the scans found ("" if none), the first that holds
/// of: references outside the vertices, no faces, polygonal faces (unless allowed), non-finite
/// coordinates, coordinates beyond kMaxCoordinate, only degenerate faces.
std::string ImportError(const VertexScan& vs, const FaceScan& fs, const TriData& out, bool allowPolygonal);
}  // namespace import_detail

/// Copies the live vertices and faces of a vcg triangle mesh into `out`.
/// Errors (nothing written to `out` is meaningful then): empty layer, point cloud (no faces),
/// polygonal faces (faux edges, when `allowPolygonal` is false), non-finite coordinates or
/// coordinates beyond kMaxCoordinate, faces
/// whose vertex references lie outside the layer's vertices or on deleted ones (a corrupt file).
/// Faces with a repeated vertex index are dropped and counted (kept with `keepDegenerate`).
template <class MeshType>
ImportReport ImportTriangles(const MeshType& m, TriData& out, bool allowPolygonal = false,
                             bool keepDegenerate = false) {
  ImportReport rep;
  out.V.clear();
  out.F.clear();
  const import_detail::VertexScan vs = import_detail::ImportVertices(m, out, rep);
  if (out.V.empty()) { rep.error = "the layer is empty (no vertices)"; return rep; }
  const import_detail::FaceScan fs = import_detail::ImportFaces(m, vs.remap, keepDegenerate, out, rep);
  rep.error = import_detail::ImportError(vs, fs, out, allowPolygonal);
  if (rep.error.empty())
    for (char u : fs.used) rep.unreferenced += u ? 0 : 1;
  return rep;
}

}  // namespace vcgext
