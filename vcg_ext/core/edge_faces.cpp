#include "vcg_ext/core/edge_faces.h"

#include <algorithm>
#include <numeric>

namespace vcgext {

EdgeFaces BuildEdgeFaces(const std::vector<Tri>& F) {
  EdgeFaces e;
  const size_t nS = F.size() * 3;
  int nV = 0;
  for (const Tri& f : F) nV = std::max({nV, f[0] + 1, f[1] + 1, f[2] + 1});
  std::vector<int> start(size_t(nV) + 1, 0);
  for (const Tri& f : F)
    for (int k = 0; k < 3; ++k) ++start[size_t(std::min(f[k], f[(k + 1) % 3])) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::pair<int, int>> byLow(nS);  // (higher end, side), bucketed by the lower end
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (size_t s = 0; s < nS; ++s) {
      const Tri& f = F[s / 3];
      const int a = f[s % 3], b = f[(s % 3 + 1) % 3];
      byLow[fill[std::min(a, b)]++] = {std::max(a, b), int(s)};
    }
  }
  e.sideEdge.resize(nS);
  e.idx.resize(nS);
  e.offs.clear();
  e.offs.reserve(nS / 2 + 1);
  for (int v = 0; v < nV; ++v) {
    std::sort(byLow.begin() + start[v], byLow.begin() + start[v + 1]);
    for (int j = start[v]; j < start[v + 1]; ++j) {
      if (j == start[v] || byLow[j].first != byLow[j - 1].first) e.offs.push_back(j);
      e.idx[j] = byLow[j].second;
      e.sideEdge[size_t(byLow[j].second)] = int(e.offs.size()) - 1;
    }
  }
  e.offs.push_back(int(nS));
  return e;
}

int OrientComponents(std::vector<Tri>& F, const EdgeFaces& e, int* components, int* nonOrientable) {
  const int nf = int(F.size());
  std::vector<int> comp(nf, -1);
  std::vector<char> flip(nf, 0);
  *components = 0;
  *nonOrientable = 0;
  int flipped = 0;
  std::vector<int> queue;
  for (int seed = 0; seed < nf; ++seed) {
    if (comp[seed] >= 0) continue;
    const int c = (*components)++;
    comp[seed] = c;
    queue.assign(1, seed);
    bool orientable = true;
    for (size_t qi = 0; qi < queue.size(); ++qi) {
      const int f = queue[qi];
      for (int k = 0; k < 3; ++k) {
        const int eid = e.sideEdge[f * 3 + k];
        if (e.offs[eid + 1] - e.offs[eid] != 2) continue;
        const int s0 = e.idx[e.offs[eid]], s1 = e.idx[e.offs[eid] + 1];
        const int g = (s0 / 3 == f) ? s1 / 3 : s0 / 3, sg = (s0 / 3 == f) ? s1 : s0;
        // same direction along the shared edge means opposite orientations
        const bool same = F[f][k] == F[g][sg % 3];
        const char want = char(flip[f] ^ (same ? 1 : 0));
        if (comp[g] < 0) {
          comp[g] = c;
          flip[g] = want;
          queue.push_back(g);
        } else if (flip[g] != want) {
          orientable = false;
        }
      }
    }
    if (!orientable) { ++*nonOrientable; continue; }
    int n = 0;
    for (int f : queue) n += flip[f];
    const bool invert = 2 * n > int(queue.size());  // keep the majority's orientation
    for (int f : queue)
      if (flip[f] != invert) { std::swap(F[f][1], F[f][2]); ++flipped; }
  }
  return flipped;
}

}  // namespace vcgext
