#pragma once
/// \file quad_cleanup.h
/// Clean-up of foreign quad control meshes before subdivision-surface evaluation.
#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Doublet removal (Fitmaps paper §3.3.3) on a whole quad mesh: every interior vertex of
/// valence 2, whose two quads (v,a,x,b) and (v,b,y,a) share two consecutive edges, is removed
/// and the quads merged into (a,x,b,y); repeated until none is left. Vertices left unreferenced
/// are dropped (indices compacted). Configurations whose merge would be degenerate (x == y)
/// are left alone. Returns the number of doublets removed. Cost: O(F) per pass, few passes.
int RemoveDoublets(QuadData& q);
/// The same on a polygonal control mesh (before SubdivideOnce): faces (v, a, P.., b) and
/// (v, b, Q.., a) round an interior vertex v of valence 2 become (a, P.., b, Q..), unless that
/// repeats a corner. A quad-dominant remesher (MeshLab's "Turn into Quad-Dominant mesh") leaves
/// such vertices, which Catmull-Clark evaluation refuses.
int RemoveDoublets(PolyData& p);
/// Interior vertices of valence 2 (doublets: every edge at them shared by two faces) of a quad or
/// polygonal mesh: after RemoveDoublets, those whose merge would repeat a corner (a closed piece
/// of two faces glued along all their edges, what pairing a tetrahedron's triangles makes), which
/// no Catmull-Clark surface has. `first` (when given): the lowest such vertex, or -1.
int CountDoublets(const QuadData& q, int* first = nullptr);
int CountDoublets(const PolyData& p, int* first = nullptr);

/// Welds the boundary vertices of equal coordinates (bitwise) of a quad control mesh exported
/// with every quad on its own vertices (an unwelded OBJ/STL-style export): without it each quad
/// is a piece of its own whose limit surface shrinks to a small patch inside the quad. Only
/// vertices on an edge of a single quad are welded: an interior vertex has its own fan of quads
/// (the copies of a vertex where two pieces touch, split on purpose, stay apart). Vertices left
/// unreferenced are dropped (indices compacted, first use order). All or nothing: when the welded
/// mesh would have a quad repeating a corner, or an edge of more than two quads or of two quads
/// running it the same way (sheets apart on purpose), `q` is left as it is. Returns the number
/// of vertices merged into another (0 when nothing changed). Cost: O(V log V + F log F).
int WeldCoincidentVertices(QuadData& q);
/// The same on a polygonal control mesh (before SubdivideOnce): an edge of one face is a
/// boundary edge.
int WeldCoincidentVertices(PolyData& p);

}  // namespace vcgext
