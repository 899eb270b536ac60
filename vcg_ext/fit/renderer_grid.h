#pragma once
/// \file renderer_grid.h
/// The displaced surface as a renderer rebuilds it (issue 15, docs/blender.md). Blender's
/// Subdivision Surface ("Use Limit Surface", level L) + Displace modifiers, like most renderers
/// that displace a subdivided mesh, evaluate the atlas only at the vertices of the uniform
/// level-L grid (2^L segments per patch side, vertices on the limit surface) and move each along
/// its mesh vertex normal: the corner-angle-weighted sum of the adjacent quads' normals (cross
/// product of the diagonals). The paper (§4) displaces along the exact limit normal and our
/// default displaced layer tessellates each patch at its own tile's spacing; the texel fit
/// (FitDisplacement) makes texels right for the surface it is given, so a renderer that
/// rebuilds another surface sees a larger error. With DisplacementAtlas::rendererLevel the
/// bake, the texel fit and the reported displaced error all use the renderer's grid.
#include <vector>

#include "vcg_ext/fit/bake.h"

namespace vcgext {

/// The uniform level-`level` grid of the limit surface (TessellateLimit with 2^level segments),
/// its `normal`s replaced by the angle-weighted quad vertex normals described above (welded
/// across patches, so a vertex on a patch edge or corner sums all its quads). level in [1, 8];
/// empty otherwise.
LimitTessellation RendererGrid(const LimitSurface& ls, const std::vector<Vec3>& ctrl, int level);

/// Vertex id of grid point (i,j), 0 <= i,j <= t.N, of patch f in a uniform tessellation
/// (TessellateLimit with one N: two triangles per cell, cells row by row, patch by patch).
int GridVertex(const LimitTessellation& t, int f, int i, int j);

/// The level whose grid has one vertex per texel along the largest tile's side (tiles of 2^k + 1
/// texels: level k), or 0 when a tile's size is not of that form (a user-set uniform R): then the
/// texels do not sit on grid vertices and the per-tile surface is used.
int RendererLevel(const DisplacementAtlas& a);

}  // namespace vcgext
