#pragma once
/// \file mesh_types.h
/// The vcg triangle-mesh type used by tests and command-line tools. It mirrors MeshLab's
/// CMeshO where the algorithms care (float coordinates, quality, colour, faux edges, FF/VF
/// adjacency, wedge texture coordinates), so the same templates run on both.
#include <vcg/complex/complex.h>

namespace vcgext {

class TVertex;
class TEdge;
class TFace;
struct TUsedTypes : public vcg::UsedTypes<vcg::Use<TVertex>::AsVertexType, vcg::Use<TEdge>::AsEdgeType,
                                          vcg::Use<TFace>::AsFaceType> {};
class TVertex : public vcg::Vertex<TUsedTypes, vcg::vertex::Coord3f, vcg::vertex::Normal3f,
                                   vcg::vertex::Qualityf, vcg::vertex::Color4b, vcg::vertex::TexCoord2f,
                                   vcg::vertex::VFAdj, vcg::vertex::Mark, vcg::vertex::BitFlags> {};
class TEdge : public vcg::Edge<TUsedTypes, vcg::edge::VertexRef, vcg::edge::BitFlags> {};
class TFace : public vcg::Face<TUsedTypes, vcg::face::VertexRef, vcg::face::Normal3f, vcg::face::Qualityf,
                               vcg::face::Color4b, vcg::face::FFAdj, vcg::face::VFAdj,
                               vcg::face::WedgeTexCoord2f, vcg::face::Mark, vcg::face::BitFlags> {};
/// Triangle mesh with the same per-element data MeshLab's CMeshO can enable.
/// vcglib 2020.09's TriMesh leaves its attribute counter `attrn` uninitialised: set here.
class TMesh : public vcg::tri::TriMesh<std::vector<TVertex>, std::vector<TFace>, std::vector<TEdge>> {
 public:
  TMesh() { attrn = 0; }
};

}  // namespace vcgext
