#include "vcg_ext/core/indexed_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <set>
#include <string>

namespace vcgext {

std::vector<int> FreeDiagonalStarts(const QuadData& q, int* blocked) {
  auto key = [](int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); };
  std::set<std::pair<int, int>> used;  // undirected mesh edges and chosen diagonals
  for (const auto& f : q.F)
    for (int k = 0; k < 4; ++k) used.insert(key(f[k], f[(k + 1) % 4]));
  std::vector<int> start(q.F.size(), 0);
  int nb = 0;
  for (size_t i = 0; i < q.F.size(); ++i) {
    const auto& f = q.F[i];
    if (used.count(key(f[0], f[2]))) {
      if (!used.count(key(f[1], f[3]))) start[i] = 1;
      else ++nb;
    }
    used.insert(key(f[start[i]], f[start[i] + 2]));
  }
  if (blocked) *blocked = nb;
  return start;
}

double BBoxDiagonal(const std::vector<Vec3>& V) {
  if (V.empty()) return 0.0;
  Vec3 lo = V[0], hi = V[0];
  for (const auto& p : V) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); }
  return (hi - lo).norm();
}

double LargestCoordinate(const std::vector<Vec3>& V) {
  double far = 0;
  for (const Vec3& p : V) far = std::max(far, p.cwiseAbs().maxCoeff());
  return far;
}

double AverageEdgeLength(const TriData& m) {
  double sum = 0.0;
  long n = 0;
  for (const auto& f : m.F)
    for (int k = 0; k < 3; ++k) {
      int a = f[k], b = f[(k + 1) % 3];
      // each interior edge appears twice (once per orientation); boundary edges once:
      // counting every half-edge gives the mean over half-edges, a negligible bias.
      sum += (m.V[a] - m.V[b]).norm();
      ++n;
    }
  return n ? sum / double(n) : 0.0;
}

double TotalArea(const TriData& m) {
  double a = 0.0;
  for (const auto& f : m.F) a += 0.5 * (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]).norm();
  return a;
}

std::vector<Vec3> FaceNormals(const TriData& m) {
  std::vector<Vec3> N(m.F.size());
  for (size_t i = 0; i < m.F.size(); ++i) {
    const auto& f = m.F[i];
    Vec3 n = (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]);
    double l = n.norm();
    N[i] = l > 0 ? Vec3(n / l) : Vec3::Zero();
  }
  return N;
}

std::vector<Vec3> VertexNormals(const TriData& m) {
  std::vector<Vec3> N(m.V.size(), Vec3::Zero());
  for (const auto& f : m.F) {
    Vec3 n = (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]);  // |n| = 2 * area
    for (int k = 0; k < 3; ++k) N[f[k]] += n;
  }
  for (auto& n : N) {
    double l = n.norm();
    n = l > 0 ? Vec3(n / l) : Vec3::Zero();
  }
  return N;
}

Adjacency VertexFaceAdjacency(const std::vector<Tri>& F, int nV) {
  Adjacency a;
  a.offs.assign(nV + 1, 0);
  for (const auto& f : F) for (int v : f) ++a.offs[v + 1];
  for (int i = 0; i < nV; ++i) a.offs[i + 1] += a.offs[i];
  a.idx.resize(a.offs[nV]);
  std::vector<int> fill(a.offs.begin(), a.offs.end() - 1);
  for (size_t fi = 0; fi < F.size(); ++fi) for (int v : F[fi]) a.idx[fill[v]++] = int(fi);
  return a;
}

std::vector<std::pair<int, int>> BoundaryHalfEdges(const TriData& m) {
  const Adjacency vf = VertexFaceAdjacency(m.F, int(m.V.size()));
  auto hasHalfEdge = [&](int a, int b) {  // some face at a has the side a -> b
    for (const int* g = vf.Begin(a); g != vf.End(a); ++g) {
      const Tri& t = m.F[*g];
      for (int k = 0; k < 3; ++k)
        if (t[k] == a && t[(k + 1) % 3] == b) return true;
    }
    return false;
  };
  std::vector<std::pair<int, int>> out;
  for (const Tri& f : m.F)
    for (int k = 0; k < 3; ++k)
      if (!hasHalfEdge(f[(k + 1) % 3], f[k])) out.push_back({f[k], f[(k + 1) % 3]});
  return out;
}

TriData SplitQuads(const QuadData& q) {
  TriData t;
  t.V = q.V;
  t.F.reserve(2 * q.F.size());
  for (const Quad& f : q.F) {
    t.F.push_back({f[0], f[1], f[2]});
    t.F.push_back({f[0], f[2], f[3]});
  }
  return t;
}

Adjacency VertexVertexAdjacency(const std::vector<Tri>& F, int nV) {
  std::vector<std::vector<int>> nb(nV);
  for (const auto& f : F)
    for (int k = 0; k < 3; ++k) {
      nb[f[k]].push_back(f[(k + 1) % 3]);
      nb[f[k]].push_back(f[(k + 2) % 3]);
    }
  Adjacency a;
  a.offs.assign(nV + 1, 0);
  for (int i = 0; i < nV; ++i) {
    auto& l = nb[i];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    a.offs[i + 1] = a.offs[i] + int(l.size());
  }
  a.idx.reserve(a.offs[nV]);
  for (auto& l : nb) a.idx.insert(a.idx.end(), l.begin(), l.end());
  return a;
}

namespace import_detail {
std::string ImportError(const VertexScan& vs, const FaceScan& fs, const TriData& out, bool allowPolygonal) {
  if (fs.badRef > 0)
    return std::to_string(fs.badRef) + " faces refer to vertices that do not exist (a corrupt or truncated "
           "file: face indices beyond the " + std::to_string(out.V.size()) + " vertices)";
  if (fs.live == 0)
    return "the layer is a point cloud (" + std::to_string(out.V.size()) +
           " vertices, no faces): a triangle mesh is needed";
  if (fs.faux > 0 && !allowPolygonal)
    return "the layer has polygonal faces (" + std::to_string(fs.faux / 2) +
           " faux edges): a triangle mesh is needed (Filters > Polygonal and Quad Mesh > "
           "Turn into a Pure-Triangular mesh)";
  if (vs.nonFinite > 0)
    return std::to_string(vs.nonFinite) + " vertices have NaN or infinite coordinates (first: vertex " +
           std::to_string(vs.firstBad) + ")";
  if (vs.huge > 0)
    return std::to_string(vs.huge) + " vertices have coordinates beyond 1e17 (first: vertex " +
           std::to_string(vs.firstHuge) + "), more than the ray caster can represent; scale the mesh down "
           "(Filters > Normals, Curvatures and Orientation > Transform: Scale, Normalize)";
  if (out.F.empty()) return "all faces are degenerate";
  return {};
}
}  // namespace import_detail

}  // namespace vcgext
