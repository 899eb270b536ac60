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

}  // namespace vcgext
