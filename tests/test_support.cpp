#include "test_support.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>

#include "vcg_ext/io/mesh_io.h"

namespace testsupport {

std::string SamplePath(const std::string& name) {
  std::string p = std::string(FITMAP_DATA_DIR) + "/" + name;
  std::ifstream f(p);
  EXPECT_TRUE(f.good()) << "sample mesh missing: " << p << " (run scripts/setup.sh)";
  return p;
}

vcgext::TriData LoadSample(const std::string& name) {
  vcgext::TMesh m;
  std::string err = vcgext::LoadMesh(SamplePath(name), m);
  EXPECT_EQ(err, "");
  vcgext::TriData d;
  auto rep = vcgext::ImportTriangles(m, d);
  EXPECT_EQ(rep.error, "");
  return d;
}

vcgext::TriData PlaneGrid(int nx, int ny, double size) {
  vcgext::TriData m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.V.emplace_back(size * i / nx, size * j / ny, 0.0);
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.F.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

vcgext::TriData GridWithZeroAreaFaces(int n, bool coincident) {
  vcgext::TriData g = HeightField(64, 64, 1.0, [](double x, double) { return x < 0.5 ? 0.0 : 0.4 * (x - 0.5) * (x - 0.5); });
  const int cells[5][2] = {{5, 5}, {10, 20}, {20, 40}, {15, 50}, {25, 10}};
  for (int k = 0; k < n; ++k) {
    const int i = cells[k][0], j = cells[k][1];
    const int a = j * 65 + i, c = j * 65 + i + 1;
    g.V[c] = coincident ? g.V[a] : vcgext::Vec3((i + 0.5) / 64, (j + 0.5) / 64, 0.0);
  }
  return g;
}

vcgext::TriData Icosphere(int level, double r) {
  vcgext::TriData m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  double pts[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : pts) m.V.push_back(vcgext::Vec3(p[0], p[1], p[2]).normalized());
  m.F = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
         {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
         {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.V.push_back((m.V[a] + m.V[b]).normalized());
      return mid[key] = int(m.V.size()) - 1;
    };
    std::vector<vcgext::Tri> nf;
    for (auto f : m.F) {
      int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      nf.push_back({f[0], a, c});
      nf.push_back({f[1], b, a});
      nf.push_back({f[2], c, b});
      nf.push_back({a, b, c});
    }
    m.F.swap(nf);
  }
  for (auto& p : m.V) p *= r;
  return m;
}

vcgext::TriData WithIsolatedHoles(const vcgext::TriData& m, int every) {
  vcgext::TriData holed;
  holed.V = m.V;
  std::vector<char> onHole(m.V.size(), 0);
  for (size_t f = 0; f < m.F.size(); ++f) {
    const auto& t = m.F[f];
    if (int(f % every) == every / 2 && !onHole[t[0]] && !onHole[t[1]] && !onHole[t[2]]) {
      for (int c = 0; c < 3; ++c) onHole[t[c]] = 1;
      continue;
    }
    holed.F.push_back(t);
  }
  return holed;
}

vcgext::TriData SphereWithHoles(int k) {
  vcgext::TriData s = Icosphere(4);
  std::vector<int> centres;
  for (int v = 0; v < int(s.V.size()) && int(centres.size()) < k; v += 7) {
    bool far = true;
    for (int c : centres) far = far && (s.V[size_t(v)] - s.V[size_t(c)]).norm() > 0.3;
    if (far) centres.push_back(v);
  }
  std::vector<vcgext::Tri> kept;
  for (const auto& f : s.F)
    if (std::none_of(centres.begin(), centres.end(), [&](int c) { return f[0] == c || f[1] == c || f[2] == c; }))
      kept.push_back(f);
  s.F = kept;
  return s;
}

void ToVcg(const vcgext::TriData& d, vcgext::TMesh& m) {
  m.Clear();
  auto vi = vcg::tri::Allocator<vcgext::TMesh>::AddVertices(m, d.V.size());
  for (size_t i = 0; i < d.V.size(); ++i, ++vi)
    vi->P() = vcg::Point3f(float(d.V[i][0]), float(d.V[i][1]), float(d.V[i][2]));
  auto fi = vcg::tri::Allocator<vcgext::TMesh>::AddFaces(m, d.F.size());
  for (size_t i = 0; i < d.F.size(); ++i, ++fi)
    for (int k = 0; k < 3; ++k) fi->V(k) = &m.vert[d.F[i][k]];
}

std::string ScratchDir() {
  static std::string dir;
  if (dir.empty()) {
    char tmpl[] = "/tmp/fitmap_test_XXXXXX";
    char* d = mkdtemp(tmpl);
    dir = d ? d : "/tmp";
  }
  return dir;
}

/// UV sphere: n longitudes, m latitude bands, one vertex per pole (valence n), outward faces.
vcgext::TriData UvSphere(int n, int m) {
  vcgext::TriData t;
  t.V.push_back(vcgext::Vec3(0, 0, 1));
  for (int i = 1; i < m; ++i)
    for (int j = 0; j < n; ++j) {
      const double th = M_PI * i / m, ph = 2 * M_PI * j / n;
      t.V.push_back(vcgext::Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  t.V.push_back(vcgext::Vec3(0, 0, -1));
  const int south = int(t.V.size()) - 1;
  auto ring = [&](int i, int j) { return 1 + (i - 1) * n + (j % n); };
  for (int j = 0; j < n; ++j) t.F.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < m; ++i)
    for (int j = 0; j < n; ++j) {
      t.F.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      t.F.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  for (int j = 0; j < n; ++j) t.F.push_back({south, ring(m - 1, j + 1), ring(m - 1, j)});
  return t;
}

}  // namespace testsupport
