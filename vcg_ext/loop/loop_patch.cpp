/// \file loop_patch.cpp
/// Regular Loop patches (§3.1): the box spline's monomial form, and the regularity test of a
/// local net that lays it on the lattice and gathers its 12 control points, with ghost points
/// across a straight crease (§2.4).
#include "vcg_ext/loop/loop_net.h"

#include <cstdlib>

namespace vcgext::loop_internal {

namespace {

// ---------------------------------------------------------------------------------------
// Box spline (§3.1). Lattice: triangle c0=(0,0), c1=(1,0), c2=(0,1); neighbours of a lattice
// point are +-(1,0), +-(0,1), +-(-1,1) (counter-clockwise: (1,0),(0,1),(-1,1),(-1,0),(0,-1),(1,-1)).
// The 12 nodes in the paper's order (Fig. 6; deduced from eq. (6) and checked independently by
// fitting the limit of regular Loop subdivision, see docs/loop.md).
const int kNode[12][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0, 2}, {-1, 2},
                          {-1, 1}, {-1, 0}, {0, -1}, {1, -1}, {2, -1}, {2, 0}};
// phi of eq. (6) times 12; columns: 1, v, w, v^2, vw, w^2, v^3, v^2w, vw^2, w^3, v^4, v^3w, v^2w^2, vw^3, w^4.
const double kPhi[12][15] = {
    {6, 0, 0, -12, -12, -12, 8, 12, 12, 8, -1, -2, 0, -2, -1},
    {1, 4, 2, 6, 6, 0, -4, -6, -12, -4, -1, -2, 0, 4, 2},
    {1, 2, 4, 0, 6, 6, -4, -12, -6, -4, 2, 4, 0, -2, -1},
    {0, 0, 0, 0, 0, 0, 2, 6, 6, 2, -1, -2, 0, -2, -1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, -2, -1},
    {1, -2, 2, 0, -6, 0, 2, 6, 0, -4, -1, -2, 0, 4, 2},
    {1, -4, -2, 6, 6, 0, -4, -6, 0, 2, 1, 2, 0, -2, -1},
    {1, -2, -4, 0, 6, 6, 2, 0, -6, -4, -1, -2, 0, 2, 1},
    {1, 2, -2, 0, -6, 0, -4, 0, 6, 2, 2, 4, 0, -2, -1},
    {0, 0, 0, 0, 0, 0, 2, 0, 0, 0, -1, -2, 0, 0, 0},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 0, 0, 0}};

}  // namespace

Patch MakePatch(const Vec3 X[12]) {
  Patch p;
  for (int m = 0; m < 15; ++m)
    for (int d = 0; d < 3; ++d) {
      double s = 0;
      for (int i = 0; i < 12; ++i) s += X[i][d] * kPhi[i][m];
      p.g[m][d] = s / 12.0;
    }
  return p;
}

namespace {

inline void Rot60(int& i, int& j) {  // (1,0)->(0,1)->(-1,1)->(-1,0)->...
  int ni = -j, nj = i + j;
  i = ni;
  j = nj;
}

// Lattice coordinate of a net vertex not (yet) placed on the lattice.
constexpr int kUnplaced = 1 << 20;

// Face adjacency inside a local net: the face across each edge, -1 if none.
std::vector<std::array<int, 3>> NetAdjacency(const LNet& n) {
  const int nf = int(n.F.size());
  std::vector<std::array<int, 3>> adj(nf, {-1, -1, -1});
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      int a = n.F[f][k], b = n.F[f][(k + 1) % 3];
      for (int g = 0; g < nf && adj[f][k] < 0; ++g) {
        if (g == f) continue;
        for (int j = 0; j < 3; ++j)
          if (n.F[g][j] == b && n.F[g][(j + 1) % 3] == a) { adj[f][k] = g; break; }
      }
    }
  return adj;
}

// A local net laid out on the lattice: vertex coordinates and the faces reached.
struct Unfolding {
  std::vector<std::array<int, 2>> co;  ///< per vertex; kUnplaced where not reached
  std::vector<char> vis;               ///< per face: reached from the target
};

// Places the vertex of face g opposite its edge (b, a) at b + Rot60(a - b); false on a clash.
bool PlaceApex(const LNet& n, int g, int a, int b, std::vector<std::array<int, 2>>& co) {
  int x = -1;
  for (int j = 0; j < 3; ++j)
    if (n.F[g][j] != a && n.F[g][j] != b) x = n.F[g][j];
  int di = co[a][0] - co[b][0], dj = co[a][1] - co[b][1];
  Rot60(di, dj);
  std::array<int, 2> cx = {co[b][0] + di, co[b][1] + dj};
  if (co[x][0] == kUnplaced) co[x] = cx;
  else if (co[x] != cx) return false;
  return true;
}

// Lays the net onto the lattice by a breadth-first search across soft edges; false on a clash.
bool Unfold(const LNet& n, Unfolding& u) {
  const int nf = int(n.F.size()), nv = int(n.P.size());
  const Tri& T = n.F[n.target];
  const std::vector<std::array<int, 3>> adj = NetAdjacency(n);
  std::vector<std::array<int, 2>>& co = u.co;
  co.assign(nv, {kUnplaced, kUnplaced});
  co[T[0]] = {0, 0};
  co[T[1]] = {1, 0};
  co[T[2]] = {0, 1};
  u.vis.assign(nf, 0);
  int queue[64], qh = 0, qt = 0;
  queue[qt++] = n.target;
  u.vis[n.target] = 1;
  while (qh < qt) {
    int f = queue[qh++];
    for (int k = 0; k < 3; ++k) {
      if (n.H[f][k]) continue;
      int g = adj[f][k];
      if (g < 0 || u.vis[g]) continue;
      if (!PlaceApex(n, g, n.F[f][k], n.F[f][(k + 1) % 3], co)) return false;
      u.vis[g] = 1;
      queue[qt++] = g;
    }
  }
  return true;
}

// The straight crease line through the patch, if any: a lattice point and a direction.
struct CreaseLine {
  bool have = false;
  int lp[2] = {0, 0}, ld[2] = {0, 0};
  // Side of the line of lattice point (i, j): the sign of the cross product, 0 on the line.
  int Side(int i, int j) const { return ld[0] * (j - lp[1]) - ld[1] * (i - lp[0]); }
};

// Faces incident to corner c (all, reached ones) and hard edges at c counted from each face.
void CountCornerFaces(const LNet& n, const std::vector<char>& vis, int c, int& incident, int& visited, int& nh) {
  const int nf = int(n.F.size());
  for (int f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j)
      if (n.F[f][j] == c) {
        ++incident;
        if (vis[f]) ++visited;
        if (n.H[f][j]) ++nh;
        if (n.H[f][(j + 2) % 3]) ++nh;
      }
}

// The two distinct hard-edge neighbours a, b of crease corner c among the reached faces.
bool HardNeighbours(const LNet& n, const std::vector<char>& vis, int c, int& a, int& b) {
  const int nf = int(n.F.size());
  a = -1;
  b = -1;
  for (int f = 0; f < nf; ++f) {
    if (!vis[f]) continue;
    for (int j = 0; j < 3; ++j)
      if (n.F[f][j] == c) {
        if (n.H[f][j]) { int o = n.F[f][(j + 1) % 3]; if (a < 0) a = o; else if (o != a) b = o; }
        if (n.H[f][(j + 2) % 3]) { int o = n.F[f][(j + 2) % 3]; if (a < 0) a = o; else if (o != a) b = o; }
      }
  }
  return a >= 0 && b >= 0;
}

// Whether c lies midway between a and b on the (first, else the same) straight crease line.
bool OnCreaseLine(const std::vector<std::array<int, 2>>& co, int a, int b, int c, CreaseLine& line) {
  if (co[a][0] + co[b][0] != 2 * co[c][0] || co[a][1] + co[b][1] != 2 * co[c][1]) return false;
  int d[2] = {co[a][0] - co[c][0], co[a][1] - co[c][1]};
  if (!line.have) {
    line.have = true;
    line.lp[0] = co[c][0]; line.lp[1] = co[c][1]; line.ld[0] = d[0]; line.ld[1] = d[1];
    return true;
  }
  // same line: direction parallel and c on it
  if (line.ld[0] * d[1] - line.ld[1] * d[0] != 0) return false;
  if (line.ld[0] * (co[c][1] - line.lp[1]) - line.ld[1] * (co[c][0] - line.lp[0]) != 0) return false;
  return true;
}

// Whether corner c is regular: smooth of valence 6, or a crease with 3 faces on a straight line.
bool CornerIsRegular(const LNet& n, const Unfolding& u, int c, CreaseLine& line) {
  int incident = 0, visited = 0, nh = 0;
  CountCornerFaces(n, u.vis, c, incident, visited, nh);
  if (n.type[c] == (unsigned char)LoopVertexType::Smooth) return incident == 6 && visited == 6 && nh == 0;
  // crease: 3 faces on this side, two collinear hard edges
  if (visited != 3) return false;
  int a = -1, b = -1;
  if (!HardNeighbours(n, u.vis, c, a, b)) return false;
  return OnCreaseLine(u.co, a, b, c, line);
}

// Side of the crease line the target lies on (+-1; 0 if all its corners are on the line).
int TargetSide(const Tri& T, const std::vector<std::array<int, 2>>& co, const CreaseLine& line) {
  // centroid*3 test with corners (at least one corner off the line)
  int tside = 0;
  for (int k = 0; k < 3; ++k) {
    int s = line.Side(co[T[k]][0], co[T[k]][1]);
    if (s != 0) tside = s > 0 ? 1 : -1;
  }
  return tside;
}

// Net vertex of each of the 12 nodes (-1 if none); false on a clash or a vertex past the crease.
bool MatchNodes(const std::vector<std::array<int, 2>>& co, const CreaseLine& line, int tside, int idx[12]) {
  const int nv = int(co.size());
  for (int m = 0; m < 12; ++m) idx[m] = -1;
  for (int v = 0; v < nv; ++v) {
    if (co[v][0] == kUnplaced) continue;
    if (line.have) {
      int s = line.Side(co[v][0], co[v][1]);
      if (s * tside < 0) return false;  // reached the other side around the end of the crease
    }
    for (int m = 0; m < 12; ++m)
      if (co[v][0] == kNode[m][0] && co[v][1] == kNode[m][1]) {
        if (idx[m] >= 0 && idx[m] != v) return false;
        idx[m] = v;
      }
  }
  return true;
}

// Net vertex at lattice point (i, j), -1 if none.
int VertexAt(const std::vector<std::array<int, 2>>& co, int i, int j) {
  const int nv = int(co.size());
  for (int v = 0; v < nv; ++v)
    if (co[v][0] == i && co[v][1] == j) return v;
  return -1;
}

// The two lattice neighbours of (gi, gj) on the crease line: (ai, aj), (bi, bj); false if not two.
bool NeighboursOnLine(const CreaseLine& line, int gi, int gj, int& ai, int& aj, int& bi, int& bj) {
  int cand[2], nc = 0;
  int di = 1, dj = 0;
  for (int r = 0; r < 6; ++r, Rot60(di, dj)) {
    int qi = gi + di, qj = gj + dj;
    if (line.Side(qi, qj) == 0 && nc < 2) cand[nc++] = r;
  }
  if (nc != 2) return false;
  ai = gi; aj = gj; bi = gi; bj = gj;
  int ti = 1, tj = 0;
  for (int r = 0; r < 6; ++r, Rot60(ti, tj)) {
    if (r == cand[0]) { ai = gi + ti; aj = gj + tj; }
    if (r == cand[1]) { bi = gi + ti; bj = gj + tj; }
  }
  return true;
}

// Ghost point of missing node m just across the crease: a + b - c (the apex c on the target side).
bool GhostPoint(const LNet& n, const std::vector<std::array<int, 2>>& co, const CreaseLine& line, int tside,
                int m, Vec3& X) {
  int gi = kNode[m][0], gj = kNode[m][1];
  int s = line.Side(gi, gj);
  if (s * tside >= 0 || std::abs(s) != 1) return false;
  // the two lattice neighbours of g on the line, and the apex on the target side
  int ai = 0, aj = 0, bi = 0, bj = 0;
  if (!NeighboursOnLine(line, gi, gj, ai, aj, bi, bj)) return false;
  int a = VertexAt(co, ai, aj), b = VertexAt(co, bi, bj), c = VertexAt(co, ai + bi - gi, aj + bj - gj);
  if (a < 0 || b < 0 || c < 0) return false;
  X = n.P[a] + n.P[b] - n.P[c];
  return true;
}

}  // namespace

bool Gather(const LNet& n, Vec3 X[12]) {
  const Tri& T = n.F[n.target];
  // corners must be smooth or crease
  for (int k = 0; k < 3; ++k)
    if (n.type[T[k]] == (unsigned char)LoopVertexType::Corner) return false;
  // A regular patch lives in at most 64 faces (the breadth-first search below); a larger net is
  // irregular. Tested before the quadratic adjacency search: the nets round a vertex of valence
  // 2000 have ~4000 faces.
  if (int(n.F.size()) > 64) return false;
  Unfolding u;
  if (!Unfold(n, u)) return false;
  CreaseLine line;
  for (int k = 0; k < 3; ++k)
    if (!CornerIsRegular(n, u, T[k], line)) return false;
  int tside = 0;
  if (line.have) {
    tside = TargetSide(T, u.co, line);
    if (tside == 0) return false;
  }
  int idx[12];
  if (!MatchNodes(u.co, line, tside, idx)) return false;
  for (int m = 0; m < 12; ++m) {
    if (idx[m] >= 0) { X[m] = n.P[idx[m]]; continue; }
    if (!line.have || !GhostPoint(n, u.co, line, tside, m, X[m])) return false;
  }
  return true;
}

}  // namespace vcgext::loop_internal
