#pragma once
/// \file fitmaps_eval.h
/// Internals of ComputeFitmaps (fitmaps.cpp), one concept per file:
/// - fitmaps_site.cpp: one vertex's evaluation, the cubic fits at growing radii with their RMS
///   residual E(r_i) (S-fitmap, §3.1.2) and flipped share (M-fitmap, §3.1.3);
/// - fitmaps_hierarchy.cpp: robust vertex normals and the vertex hierarchy of Fast mode.
/// Decisions where the paper is ambiguous: docs/fitmaps.md.
#include "vcg_ext/fitmaps/fitmaps.h"
#include "vcg_ext/fitmaps/fitmaps_internal.h"

#include <vector>

namespace vcgext::fitmaps_internal {

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

/// What one evaluation computes.
struct EvalSpec {
  int start = 0;        ///< level point the traversal starts from
  int vertex = 0;       ///< mesh vertex: origin, normal and random stream of the tangent frame
  bool doS = true, doM = true;
  bool literal = false;        ///< Reference mode M (forward rays from the paper's samples)
  bool stopMAtFailure = true;  ///< skip M for radii after the first failing one
};

/// Evaluates radii [iBegin, iEnd) for the frame of mesh vertex `e.vertex`, gathering the points
/// of level `lv` (level 0 = the mesh). Writes out.E/eOk (doS) and out.phi/phiOk (doM).
void Evaluate(const Context& ctx, const Level& lv, const EvalSpec& e, int iBegin, int iEnd, Scratch& s,
              RadiusValues& out);

/// Area-weighted normals; where they vanish (unreferenced vertex, faces cancelling at a
/// non-manifold vertex), the PCA normal of the 30 nearest vertices of the connected
/// neighbourhood; zero if that is undefined too (a single isolated vertex).
std::vector<Vec3> RobustNormals(const TriData& m, const Adjacency& vv, double rMax, int& fallbacks);

/// Level 0 of the hierarchy: the mesh; faces belong to the cluster of their first corner.
Level MakeFineLevel(const TriData& m, const Adjacency& vv, double totalArea);

/// Cluster -> faces lists with cumulative areas (face f belongs to the cluster of F[f][0]).
void BuildClusterFaces(const TriData& m, const std::vector<double>& faceArea, Level& lv);

/// Next coarser level: seeds greedily covering the level within `cover` (connected traversal,
/// so clusters never join separate components), every point assigned to its graph-nearest seed
/// (multi-source Dijkstra on edge lengths), clusters adjacent when any members are.
Level Coarsen(const Level& f, double cover);

}  // namespace vcgext::fitmaps_internal
