#pragma once
/// \file quad_mesh.h
/// An editable pure-quad mesh for the local operators of Fitmaps §3.3 (diagonal collapse, edge
/// swap, doublet removal): indexed quads with per-vertex incident-face lists kept up to date,
/// implicit half-edges (half-edge k of face f goes from corner k to corner k+1), a journal that
/// can roll back a whole step, and a validity checker.
///
/// Every operator applies its edit, checks the touched neighbourhood (pure quads, manifold fans,
/// valence rules) and rolls the edit back when the check fails, returning a reason code: the
/// mesh is never left invalid. Operators never create elements (indices stay stable); removed
/// faces/vertices are flagged dead.
///
/// Valence rules (decision, see docs/quad.md): interior vertices need valence >= 3 (a valence-2
/// interior vertex is a doublet, removed at once); a boundary vertex needs at least one face, so
/// boundary "corners" of valence 2 (one face, e.g. the corners of a grid) are allowed. Boundary
/// vertices stay boundary vertices: an operator that would merge two boundary vertices is refused.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {
namespace quad {

/// Why an operator refused (Ok = applied).
enum class OpResult {
  Ok,
  DeadElement,        ///< the face/vertex does not exist any more
  BoundaryMerge,      ///< would merge two boundary vertices (changes boundary loops)
  BoundaryEdge,       ///< edge swap on a boundary edge
  NotDoublet,         ///< doublet removal on a vertex that is not an interior valence-2 vertex
                      ///< (or boundary-corner removal on a vertex that is not a one-face boundary vertex)
  Degenerate,         ///< would create a face with a repeated vertex
  NonManifold,        ///< would create a non-manifold edge or vertex (link condition)
  LowValence,         ///< would leave an interior vertex with valence < 3 or a boundary vertex without faces
  NoImprovement,      ///< edge swap that does not strictly lower the valence energy
};
const char* ToString(OpResult r);

/// One corner of a vertex's fan: face f has v at corner k; n = next corner, o = opposite, p = previous.
struct Wedge {
  int f, k, n, o, p;
};

class QuadMesh {
 public:
  QuadMesh() = default;
  /// Builds from arrays (faces counter-clockwise). Does not validate: call Check().
  QuadMesh(const std::vector<Vec3>& V, const std::vector<Quad>& F);

  // ------------------------------------------------------------------ access
  int NumVertexSlots() const { return int(P.size()); }
  int NumFaceSlots() const { return int(F.size()); }
  int NumFaces() const { return nFaces_; }
  int NumVertices() const { return nVerts_; }
  bool FaceAlive(int f) const { return faceAlive_[f] != 0; }
  /// Itself (so that cc_limit's stencils take a QuadMesh or a QuadMemo alike).
  const QuadMesh& Mesh() const { return *this; }
  bool VertAlive(int v) const { return vertAlive_[v] != 0; }
  bool IsBoundary(int v) const { return boundary_[v] != 0; }
  const std::vector<int>& VF(int v) const { return vf_[v]; }
  /// Number of incident edges (interior: faces; boundary: faces + 1).
  int Valence(int v) const { return int(vf_[v].size()) + (boundary_[v] ? 1 : 0); }
  /// Regular valence: 4 inside, 3 on the boundary.
  int RegularValence(int v) const { return boundary_[v] ? 3 : 4; }
  /// Ordered fan of v: wedges w[0..m) with w[i+1].p == w[i].n (a clockwise walk). For a boundary
  /// vertex w[0].p and w[m-1].n are its two boundary neighbours. Returns false if the fan is not
  /// a single disk / half-disk (non-manifold vertex).
  bool Fan(int v, std::vector<Wedge>& w, bool* open = nullptr) const;
  /// Face on the other side of the edge from corner k of face f (-1 on the boundary).
  int AcrossEdge(int f, int k) const;
  /// Corner of `v` in face f (-1 if absent).
  int CornerOf(int f, int v) const;
  /// Centroid of a face's control points.
  Vec3 Centroid(int f) const;

  // ------------------------------------------------------------------ operators (§3.3)
  /// Diagonal collapse of face f along the diagonal through corners k and k+2 (k = 0 or 1).
  /// The survivor is the boundary corner if there is one (it keeps its position), otherwise
  /// corner k placed at the midpoint. `survivor` receives its index. Fig. 4 of the paper.
  OpResult CollapseDiagonal(int f, int k, int* survivor = nullptr);
  /// Rotates the interior edge from corner k of face f to one of the two other diagonals of the
  /// hexagon formed by its two faces (`variant` 0 or 1). Touches only connectivity.
  OpResult SwapEdge(int f, int k, int variant);
  /// Merges the two faces of an interior valence-2 vertex v (doublet) and removes v.
  OpResult RemoveDoublet(int v);
  /// Boundary counterpart of doublet removal (decision, see docs/quad.md): a boundary vertex b
  /// with a single face (a, b, c, d) (boundary valence 2) is removed with that face and its two
  /// boundary neighbours a, c are merged (at their midpoint): the boundary loses two vertices,
  /// Euler characteristic and boundary loops are unchanged. Diagonal collapses alone can never
  /// reduce the number of boundary vertices (merging two boundary vertices across a face would
  /// pinch the surface), so this is what lets open boundaries coarsen.
  /// `keep`: 0 = survivor a at the midpoint of a and c, 1 = survivor a at its position,
  /// 2 = survivor c at its position.
  OpResult RemoveBoundaryCorner(int b, int* survivor = nullptr, int keep = 0);
  /// Valence energy sum |D(v) - regular(v)| over the distinct corners of faces f and g.
  int ValenceEnergy(int f, int g) const;
  /// Energy change of SwapEdge(f, k, variant) without applying it (positive = worse);
  /// returns false if the edge is on the boundary.
  bool SwapEnergyDelta(int f, int k, int variant, int* delta) const;

  // ------------------------------------------------------------------ transactions
  /// Starts recording changes; Rollback() restores everything since then, Commit() forgets.
  /// Operators journal their own edits (and undo them when refused) also outside a transaction.
  void Begin();
  void Commit();
  void Rollback();
  bool InTransaction() const { return recording_; }
  /// A point of the running transaction's journal; UndoTo(mark) restores the mesh as it was
  /// there and keeps the transaction open (a search that tries operators and backs out).
  struct Mark {
    size_t faces = 0, verts = 0;
  };
  Mark JournalMark() const { return {fj_.size(), vj_.size()}; }
  void UndoTo(const Mark& m) { RollbackTo(m.faces, m.verts); }
  /// Moves a control point, journaled when inside a transaction.
  void MoveVertex(int v, const Vec3& p);

  // ------------------------------------------------------------------ validity
  /// Topological invariants recorded once and compared by Check().
  struct Invariants {
    int components = 0;
    std::vector<int> eulerPerComponent;  ///< sorted
    int boundaryLoops = 0;
    std::vector<int> boundaryLoopsPerComponent;  ///< sorted together with euler (paired)
  };
  Invariants ComputeInvariants() const;
  /// Full check: live faces are quads of 4 distinct live vertices, incident-face lists agree
  /// with the faces, each directed half-edge occurs once and each edge has at most two faces
  /// (opposite orientations = half-edge twins), every vertex fan is one disk or half-disk,
  /// boundary flags agree with the fans, interior valence >= 3 (no valence-2 vertex), live
  /// vertices have faces; if `ref` is given, components, Euler characteristic per component and
  /// boundary loops must equal it. Returns "" if valid, else the first problem found. O(F).
  std::string Check(const Invariants* ref = nullptr) const;

  /// Live faces and vertices as compact arrays; `vmap` (optional) maps slots to new indices.
  QuadData ToQuadData(std::vector<int>* vmap = nullptr) const;
  /// Histogram of valences of live vertices (index = valence); irregular count alongside.
  std::vector<int> ValenceHistogram(int* irregular = nullptr) const;

  std::vector<Vec3> P;   ///< control points (slots; dead ones are stale)
  std::vector<Quad> F;   ///< faces (slots)

 private:
  void SaveFace(int f);
  void SaveVert(int v);
  void RemoveVF(int v, int f);
  void KillFace(int f);
  void RollbackTo(size_t fmark, size_t vmark);
  void EndOp(size_t fmark, size_t vmark, bool ok);
  OpResult LocalCheck(const std::vector<int>& verts, bool allowDoublets) const;

  std::vector<char> faceAlive_, vertAlive_, boundary_;
  std::vector<std::vector<int>> vf_;
  int nFaces_ = 0, nVerts_ = 0;

  // journal
  struct FaceRec { int f; Quad q; char alive; };
  struct VertRec { int v; Vec3 p; char alive; bool posOnly; std::vector<int> vf; };
  bool recording_ = false;
  std::vector<FaceRec> fj_;  // appended on every save; restored in reverse order
  std::vector<VertRec> vj_;
};

}  // namespace quad
}  // namespace vcgext
