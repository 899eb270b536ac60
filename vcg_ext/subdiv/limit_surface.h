#pragma once
/// \file limit_surface.h
/// The project's OpenSubdiv 3.5 adapter: exact Catmull-Clark and Loop limit evaluation of a
/// control mesh, as positions/derivatives or as *stencils* (weights on the control points), the
/// rows of the least-squares fits of Fitmaps §3.4–3.5 (system (1) and its sampled extension).
///
/// Built on Far::TopologyRefinerFactory<Far::TopologyDescriptor> (topology only, no refinement)
/// and Bfr::RefinerSurfaceFactory / Bfr::Surface<double> (one Surface per base face, built once
/// in the constructor).
///
/// (u,v) convention (Bfr's, per base face, corners in the face's vertex order):
///  - quad (Catmull-Clark): [0,1]^2, corner k at (0,0), (1,0), (1,1), (0,1);
///  - triangle (Loop): u,v >= 0, u+v <= 1, corner k at (0,0), (1,0), (0,1);
///  - other n-gons (Catmull-Clark only, "quad sub-faces"): see Bfr::Parameterization; use
///    `Parameterization(face)` / `CornerUV` rather than hard-coding.
/// Du, Dv are the partial derivatives with respect to these u, v (not normalized).
///
/// Boundaries: Sdc VTX_BOUNDARY_EDGE_ONLY by default (boundary edges are infinitely sharp,
/// boundary curves are cubic B-splines, valence-2 boundary corners stay smooth); set
/// `sharpBoundaryCorners` for VTX_BOUNDARY_EDGE_AND_CORNER. Face-varying data is not used.
///
/// Exactness: regular faces are evaluated exactly (bicubic B-spline / quartic box-spline).
/// Faces at extraordinary vertices use Bfr's irregular patch: exact limit position and tangents
/// at the extraordinary vertex itself, exact away from it, and a Gregory-patch end cap in a
/// region of size 2^-approxLevelSmooth of the face around it (see Bfr::SurfaceFactory::Options).
///
/// Thread safety: all const methods may be called concurrently. The Bfr factory (and its
/// non-threaded cache) is only used inside the constructor; queries use the prebuilt, read-only
/// Bfr::Surface objects and per-call scratch buffers.
#include <Eigen/Sparse>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

enum class SubdivScheme { CatmullClark, Loop };

/// Options of LimitSurface. Sharp features are infinitely sharp (semi-sharp creases are not
/// exposed: the fits of this project do not need them).
struct LimitSurfaceOptions {
  SubdivScheme scheme = SubdivScheme::CatmullClark;
  std::vector<std::pair<int, int>> creaseEdges;  ///< infinitely sharp edges (vertex pairs; must be mesh edges)
  std::vector<int> cornerVertices;               ///< infinitely sharp vertices
  bool sharpBoundaryCorners = false;             ///< VTX_BOUNDARY_EDGE_AND_CORNER instead of EDGE_ONLY
  int approxLevelSmooth = 4;  ///< Bfr refinement depth around smooth extraordinary vertices (1..10)
  int approxLevelSharp = 6;   ///< Bfr refinement depth around sharp irregular features (1..10)
  /// Refuse a vertex of more edges, or a face of more sides, than this (0: no limit). Each face
  /// at a vertex of valence n has a patch of about 2n + 8 control points, so the surface takes
  /// about 140 n² bytes round it (measured: valence 2 048, 0.58 GB and 1.2 s to build; 8 192
  /// would take ~9 GB); an n-gon's patch is that of its face point, of valence n (a 3 000-gon
  /// took 8 minutes to build). Same limit as the Loop filters' LoopSurfaceParams::maxValence.
  int maxValence = 2048;
};

/// Limit point (and derivatives) as sparse weights on the control vertices:
/// P = sum_i P[i] * ctrl[index[i]] (same for Du, Dv, Duu, Duv, Dvv). Indices are unique and
/// sorted. Derivative arrays are empty unless requested.
struct LimitStencil {
  std::vector<int> index;
  std::vector<double> P, Du, Dv, Duu, Duv, Dvv;
  int Size() const { return int(index.size()); }
};

class LimitSurface {
 public:
  /// Builds the limit-surface evaluator of a polygonal control mesh (faces as sizes + flat vertex
  /// lists, counter-clockwise). Validates the topology first: vertex indices in range, face sizes
  /// (>= 3; exactly 3 for Loop), no repeated vertex in a face, every edge used by at most two
  /// faces with opposite orientations (manifold, consistently oriented), crease edges exist,
  /// corner indices in range. On failure `Ok()` is false and `Error()` says what is wrong (which
  /// element, how many), or a vertex / face above `opt.maxValence`. Cost: O(F) plus one Bfr::Surface per face (irregular faces share their
  /// patch through the factory cache).
  LimitSurface(int numVertices, const std::vector<int>& faceSizes, const std::vector<int>& faceVerts,
               const LimitSurfaceOptions& opt = {});
  /// The constructor's checks without building the surface: "" or the error `Error()` would
  /// give. Cost: O(F log F).
  static std::string CheckTopology(int numVertices, const std::vector<int>& faceSizes,
                                   const std::vector<int>& faceVerts, const LimitSurfaceOptions& opt = {});
  /// Catmull-Clark (by default) limit of a pure-quad mesh; `opt.scheme` is forced to CatmullClark.
  static LimitSurface FromQuads(const QuadData& q, LimitSurfaceOptions opt = {});
  /// Loop limit of a triangle mesh; `opt.scheme` is forced to Loop.
  static LimitSurface FromTriangles(const TriData& t, LimitSurfaceOptions opt = {});

  LimitSurface(LimitSurface&&) noexcept;
  LimitSurface& operator=(LimitSurface&&) noexcept;
  ~LimitSurface();

  bool Ok() const { return error_.empty(); }
  const std::string& Error() const { return error_; }
  SubdivScheme Scheme() const { return opt_.scheme; }
  int NumVertices() const { return numVertices_; }
  int NumFaces() const { return int(faceOffs_.size()) - 1; }
  int FaceSize(int face) const { return faceOffs_[face + 1] - faceOffs_[face]; }
  /// Control vertex of the face's k-th corner.
  int FaceVertex(int face, int k) const { return faceVerts_[faceOffs_[face] + k]; }
  /// Number of control points the face's limit patch depends on (the length of its stencils
  /// before duplicates are merged): 16 for a regular quad, about 2n + 8 round a vertex of valence n.
  int NumPatchPoints(int face) const;
  /// Whether the face's limit patch is a single regular B-spline / box-spline patch.
  bool FaceIsRegular(int face) const;
  /// Number of irregular (extraordinary) vertices: interior valence != 4 (CC) / 6 (Loop),
  /// boundary valence != 3 (CC) / 4 (Loop); isolated vertices are not counted.
  int NumIrregularVertices() const { return numIrregular_; }
  /// Valence (number of incident edges) of each vertex.
  const std::vector<int>& Valences() const { return valence_; }
  /// (u,v) of the face's k-th corner in its parameterization (see the file comment).
  void CornerUV(int face, int k, double& u, double& v) const;

  /// Limit point and derivatives up to `order` (0, 1 or 2) at (face,u,v) as weights on the
  /// control points. Returns false (and leaves `out` empty) for an invalid face index or when
  /// `Ok()` is false. Cost: O(stencil size), typically 16–40 weights.
  bool Stencil(int face, double u, double v, LimitStencil& out, int order = 1) const;
  /// Evaluates the limit (and the non-null derivatives) at (face,u,v) for control points `ctrl`
  /// (size NumVertices()). Returns false on invalid input.
  bool Evaluate(int face, double u, double v, const std::vector<Vec3>& ctrl, Vec3* P, Vec3* Du = nullptr,
                Vec3* Dv = nullptr, Vec3* Duu = nullptr, Vec3* Duv = nullptr, Vec3* Dvv = nullptr) const;
  /// Limit positions of the control vertices as a sparse NumVertices() x NumVertices() matrix L
  /// (V_limit = L * V_ctrl): the left-hand side of system (1) of the paper (§3.4). Rows of
  /// isolated vertices (no incident face) are identity rows. Empty matrix if !Ok().
  Eigen::SparseMatrix<double> VertexLimitMatrix() const;

 private:
  LimitSurface() = default;
  void Build(int numVertices, const std::vector<int>& faceSizes, const std::vector<int>& faceVerts);
  std::string Validate(int numVertices, const std::vector<int>& faceSizes, const std::vector<int>& faceVerts);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  LimitSurfaceOptions opt_;
  std::string error_;
  int numVertices_ = 0;
  int numIrregular_ = 0;
  std::vector<int> faceOffs_, faceVerts_, valence_;
  std::vector<std::pair<int, int>> vertexCorner_;  ///< (face, corner) of one incident face per vertex, or (-1,-1)
};

}  // namespace vcgext
