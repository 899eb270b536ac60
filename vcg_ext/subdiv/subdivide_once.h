#pragma once
/// \file subdivide_once.h
/// One Catmull-Clark subdivision step of a polygonal control mesh: how a cage with triangles or
/// n-gons among its quads (a quad-dominant retopology, a hand-made cage) becomes the pure-quad
/// control mesh that the fit of Fitmaps §3.4–3.5 works on, with the same limit surface.
#include <string>

#include "vcg_ext/core/indexed_mesh.h"

namespace vcgext {

/// Subdivides `p` once by Catmull-Clark (OpenSubdiv Far: uniform refinement to level 1, the
/// positions by Far::PrimvarRefiner, with LimitSurface's default Sdc options: boundary edges
/// sharp, boundary corners smooth). Every n-gon becomes n quads round a new face point, so `out`
/// is pure quads with V + E + F vertices (the first |V| are the input's vertices, moved by the
/// subdivision rules, in the input's order), and its Catmull-Clark limit surface is the input's:
/// Catmull-Clark is defined on polygons by this first step (LimitSurface evaluates n-gons so).
/// Returns "" or what is wrong with the topology (LimitSurface's validation: faces of fewer than
/// three vertices, a repeated corner, an edge of more than two faces or of two running it the
/// same way, indices out of range, a vertex above LimitSurfaceOptions::maxValence, which an n-gon
/// of more sides gives its face point); `out` is left empty then. Cost: O(V + F).
std::string SubdivideOnce(const PolyData& p, QuadData& out);

}  // namespace vcgext
