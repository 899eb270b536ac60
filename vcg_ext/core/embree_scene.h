#pragma once
/// \file embree_scene.h
/// The project's single Embree 3 adapter: a triangle scene built once (RAII), queried many
/// times from any number of threads (all query methods are const and thread-safe).
/// Used for the Fitmaps' ray casts (paper §3.1.3), the projection phi along the limit normal
/// (§3.2–3.5) and the displacement bake.
#include "vcg_ext/core/indexed_mesh.h"

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace vcgext {

struct BoundarySegments;

/// Bounding-box diagonals within which EmbreeScene hands Embree the coordinates as they are;
/// outside, they are scaled by a power of two (EmbreeScene::scale_; distances and points come
/// back in the mesh's units). Embree's ray-triangle test works in float and clamps its
/// determinant below 1e-18 (min_rcp_input): on an icosphere 2^-27 across every hit came back at
/// a triangle corner (u = v = 0; 2^-26 was still exact), and at 2^50 no ray hit. Inside the
/// window (a margin on both sides) nothing changes, bit for bit.
constexpr double kMinUnscaledDiagonal = 1.0 / 4096, kMaxUnscaledDiagonal = 1 << 24;

class EmbreeScene {
 public:
  /// Builds the BVH over `m` (vertices converted to float, as Embree requires).
  /// On failure `Ok()` is false and `Error()` says why; queries then report no hit.
  explicit EmbreeScene(const TriData& m);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  bool Ok() const { return scene_ != nullptr; }
  const std::string& Error() const { return error_; }

  struct Hit {
    bool valid = false;
    double t = 0;      ///< signed ray parameter (distance, for a unit direction)
    int face = -1;     ///< index into the TriData's F
    double u = 0, v = 0;  ///< barycentrics of corners 1 and 2 (corner 0 has 1-u-v)
    Vec3 point = Vec3::Zero();
  };

  /// First hit of the ray org + t*dir, t in [tnear, tfar]. `dir` need not be unit.
  Hit Intersect(const Vec3& org, const Vec3& dir, double tnear = 0.0,
                double tfar = std::numeric_limits<double>::infinity()) const;
  /// Nearest hit on the whole line through `org` along ±dir, within |t| <= maxDist
  /// (`dir` unit): the paper's projection phi "along the normal", either side.
  Hit IntersectLine(const Vec3& org, const Vec3& dir,
                    double maxDist = std::numeric_limits<double>::infinity()) const;
  /// Same query as the projection phi along the normal, fewer rays: the nearest hit on the line
  /// through `c` along ±dir (`dir` unit), |t| <= maxDist, ties to +dir (up to float rounding).
  /// A surface through c is found. `side` (in/out, optional) is a guess of the side of the
  /// answer (+1 along dir, -1 against), updated with the side found; `window` > 0 is the
  /// distance within which the answer is usually found. One ray from c - window·side·dir covers
  /// both sides near c: when its first hit lies on the guessed side within the window, it is the
  /// answer (1 ray instead of 2); otherwise 1 or 2 more rays settle it. The result does not depend
  /// on the guess or the window (tests/core: brute-force comparison); only the ray count does.
  Hit NearestOnLine(const Vec3& c, const Vec3& dir, double maxDist, double window,
                    signed char* side = nullptr) const;
  /// Closest point on the surface within `maxDist` (Embree point query). When nothing lies
  /// within maxDist the answer may still be a triangle somewhat beyond it (Embree hands the
  /// callback every triangle of a leaf whose box meets the query sphere), or none: callers that
  /// need the bound check the distance. `hintFace` (optional,
  /// -1 = none): a face probably near the answer, e.g. the previous answer of a loop over
  /// neighbouring points. Its distance bounds the query radius from the start, so the traversal
  /// skips most of the tree; the answer is the same (every face at the minimum distance stays
  /// inside the radius), only faster: 2-4x on dense meshes, where an unbounded query visits many
  /// leaves before its radius shrinks (tests/core: brute-force comparison with and without).
  Hit ClosestPoint(const Vec3& p, double maxDist = std::numeric_limits<double>::infinity(),
                   int hintFace = -1) const;
  /// Closest point to p on the mesh's boundary (its edges of one triangle; invalid when it has
  /// none), by a second BVH over those edges (an Embree user geometry built with the scene):
  /// `t` its distance, `face` the boundary edge's index in BoundaryEdges(). The same point as a
  /// loop over all the edges (tests/core: brute-force comparison), in O(log) instead of O(edges):
  /// a scan with thousands of holes or floating specks has tens of thousands of them.
  Hit ClosestBoundaryPoint(const Vec3& p) const;
  /// The boundary edges (BoundaryHalfEdges of the mesh) ClosestBoundaryPoint searches.
  const std::vector<std::pair<int, int>>& BoundaryEdges() const { return boundary_; }

  const TriData& Mesh() const { return mesh_; }

 private:
  TriData mesh_;
  double eps_ = 0;  ///< 1e-7 x bbox diagonal: rays from a point start this far behind it
  double coordScale_ = 0;  ///< largest |coordinate| (float rounding bound of the hint radius)
  /// Embree's frame: its float copy of the mesh, ray origins and query points are these
  /// coordinates times scale_, a power of two (exact): 1 unless the bbox diagonal lies outside
  /// [kMinUnscaledDiagonal, kMaxUnscaledDiagonal], then the one that brings it into [1, 2).
  double scale_ = 1;
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  void BuildBoundaryScene();
  std::vector<std::pair<int, int>> boundary_;
  std::unique_ptr<BoundarySegments> segments_;
  RTCSceneTy* boundaryScene_ = nullptr;  ///< user geometry over boundary_ (none without a boundary)
  std::string error_;
};

/// Closest point to p on triangle (a,b,c); returns it and the barycentrics (of b and c).
Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            double* u = nullptr, double* v = nullptr);

}  // namespace vcgext
