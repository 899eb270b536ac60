#include "vcg_ext/core/quad_cleanup.h"

#include <algorithm>
#include <map>
#include <tuple>
#include <type_traits>

namespace vcgext {

namespace {
// Rotates face f so that corner `v` comes first; false if v is not a corner.
template <class Face>
bool RotateTo(Face& f, int v) {
  for (size_t k = 0; k < f.size(); ++k)
    if (f[k] == v) {
      std::rotate(f.begin(), f.begin() + long(k), f.end());
      return true;
    }
  return false;
}

// The vertices of V that F uses, in order of first use; F renumbered to them.
template <class Face>
std::vector<Vec3> CompactVertices(std::vector<Face>& F, const std::vector<Vec3>& V) {
  std::vector<int> remap(V.size(), -1);
  std::vector<Vec3> out;
  for (Face& f : F)
    for (int& c : f) {
      if (remap[c] < 0) {
        remap[c] = int(out.size());
        out.push_back(V[c]);
      }
      c = remap[c];
    }
  return out;
}

// The face of corners c: two quads less their doublet make a quad.
template <class Face>
Face FaceOf(const std::vector<int>& c) {
  if constexpr (std::is_same_v<Face, Quad>) return {c[0], c[1], c[2], c[3]};
  else return c;
}

// RemoveDoublets on any faces (quads, polygons): faces (v, a, P.., b) and (v, b, Q.., a) become
// (a, P.., b, Q..).
template <class Face>
int RemoveDoubletsOf(std::vector<Vec3>& V, std::vector<Face>& faces) {
  int removed = 0;
  std::vector<char> dead(faces.size(), 0);
  for (bool changed = true; changed;) {
    changed = false;
    const int nV = int(V.size());
    std::vector<std::vector<int>> facesAt(nV);
    std::map<std::pair<int, int>, int> edgeCount;
    for (size_t f = 0; f < faces.size(); ++f) {
      if (dead[f]) continue;
      const size_t n = faces[f].size();
      for (size_t k = 0; k < n; ++k) {
        facesAt[faces[f][k]].push_back(int(f));
        ++edgeCount[std::minmax(faces[f][k], faces[f][(k + 1) % n])];
      }
    }
    std::vector<char> touched(faces.size(), 0);
    for (int v = 0; v < nV; ++v) {
      if (facesAt[v].size() != 2) continue;
      int f1 = facesAt[v][0], f2 = facesAt[v][1];
      if (touched[f1] || touched[f2]) continue;
      Face a1 = faces[f1], a2 = faces[f2];
      RotateTo(a1, v);
      RotateTo(a2, v);
      // a1 = (v, a, P.., b), a2 must be (v, b, Q.., a); both edges interior (shared by the two).
      const int a = a1[1], b = a1.back();
      if (a2[1] != b || a2.back() != a) continue;
      if (edgeCount[std::minmax(v, a)] != 2 || edgeCount[std::minmax(v, b)] != 2) continue;
      std::vector<int> merged(a1.begin() + 1, a1.end());  // a, P.., b
      merged.insert(merged.end(), a2.begin() + 2, a2.end() - 1);  // Q..
      std::vector<int> sorted = merged;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;  // degenerate
      faces[f1] = FaceOf<Face>(merged);
      dead[f2] = 1;
      touched[f1] = touched[f2] = 1;
      ++removed;
      changed = true;
    }
  }
  // Compact faces, then vertices.
  std::vector<Face> F;
  for (size_t f = 0; f < faces.size(); ++f)
    if (!dead[f]) F.push_back(faces[f]);
  if (removed == 0) return 0;  // keep vertex order (and unreferenced vertices) when nothing changed
  V = CompactVertices(F, V);
  faces.swap(F);
  return removed;
}
}  // namespace

int RemoveDoublets(QuadData& q) { return RemoveDoubletsOf(q.V, q.F); }

int RemoveDoublets(PolyData& p) { return RemoveDoubletsOf(p.V, p.F); }

namespace {
template <class Face>
int CountDoubletsOf(size_t nV, const std::vector<Face>& faces, int* first) {
  std::map<std::pair<int, int>, int> edgeUse;
  for (const Face& f : faces)
    for (size_t k = 0; k < f.size(); ++k) ++edgeUse[std::minmax(f[k], f[(k + 1) % f.size()])];
  std::vector<int> valence(nV, 0);
  std::vector<char> boundary(nV, 0);
  for (const auto& [e, n] : edgeUse) {
    ++valence[e.first];
    ++valence[e.second];
    if (n == 1) boundary[e.first] = boundary[e.second] = 1;
  }
  int count = 0;
  if (first) *first = -1;
  for (size_t v = 0; v < nV; ++v)
    if (valence[v] == 2 && !boundary[v]) {
      if (first && *first < 0) *first = int(v);
      ++count;
    }
  return count;
}
}  // namespace

int CountDoublets(const QuadData& q, int* first) { return CountDoubletsOf(q.V.size(), q.F, first); }

int CountDoublets(const PolyData& p, int* first) { return CountDoubletsOf(p.V.size(), p.F, first); }

namespace {
// Whether every face has distinct corners and every edge is used by at most two faces, running
// it in opposite directions.
template <class Face>
bool EdgeManifoldAndOriented(const std::vector<Face>& F) {
  std::map<std::pair<int, int>, int> directed;
  for (const Face& f : F) {
    const int n = int(f.size());
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < k; ++j)
        if (f[j] == f[k]) return false;
      if (++directed[{f[k], f[(k + 1) % n]}] > 1) return false;  // twice the same way (or 3+ faces)
    }
  }
  return true;
}

// WeldCoincidentVertices on any faces (quads, polygons).
template <class Face>
int WeldBoundaryVertices(std::vector<Vec3>& V, std::vector<Face>& faces) {
  // Vertices on an edge of one face: only they are welded (an interior vertex has its fan).
  std::map<std::pair<int, int>, int> edgeUse;
  for (const Face& f : faces)
    for (size_t k = 0; k < f.size(); ++k) ++edgeUse[std::minmax(f[k], f[(k + 1) % f.size()])];
  std::vector<char> boundary(V.size(), 0);
  for (const auto& [e, n] : edgeUse)
    if (n == 1) boundary[e.first] = boundary[e.second] = 1;
  auto key = [&](int v) { return std::make_tuple(V[v].x(), V[v].y(), V[v].z()); };
  std::map<std::tuple<double, double, double>, int> first;
  std::vector<int> into(V.size());
  int merged = 0;
  for (int v = 0; v < int(V.size()); ++v) {
    into[v] = v;
    if (!boundary[v]) continue;
    auto [it, isNew] = first.emplace(key(v), v);
    into[v] = it->second;
    if (!isNew) ++merged;
  }
  if (merged == 0) return 0;
  std::vector<Face> F = faces;
  for (Face& f : F)
    for (int& c : f) c = into[c];
  if (!EdgeManifoldAndOriented(F)) return 0;
  V = CompactVertices(F, V);
  faces.swap(F);
  return merged;
}
}  // namespace

int WeldCoincidentVertices(QuadData& q) { return WeldBoundaryVertices(q.V, q.F); }

int WeldCoincidentVertices(PolyData& p) { return WeldBoundaryVertices(p.V, p.F); }

}  // namespace vcgext
