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

}  // namespace vcgext
