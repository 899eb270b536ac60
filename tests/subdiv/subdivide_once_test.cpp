// SubdivideOnce against OpenSubdiv's own evaluation of the polygonal mesh: the limit surface of
// the subdivided quads (this project's LimitSurface, Bfr on quads) must be the polygon mesh's
// Catmull-Clark limit (Bfr on its triangles, quads and pentagons directly, through their
// parameterizations), point for point.
#include <gtest/gtest.h>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <array>
#include <memory>
#include <random>
#include <set>

#include "vcg_ext/subdiv/limit_surface.h"
#include "vcg_ext/subdiv/subdivide_once.h"

using vcgext::PolyData;
using vcgext::QuadData;
using vcgext::Vec3;

namespace {
namespace osd = OpenSubdiv;

// A pentagonal prism (two pentagons, five sides) with one side split into two triangles along a
// diagonal: faces of 3, 4 and 5 corners, counter-clockwise from outside; vertices jittered so that
// nothing is symmetric. `open` drops the last side: a boundary loop.
PolyData MixedPrism(bool open) {
  PolyData p;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  for (int ring = 0; ring < 2; ++ring)
    for (int k = 0; k < 5; ++k) {
      const double a = 2 * M_PI * k / 5;
      p.V.push_back(Vec3(std::cos(a) + jitter(rng), std::sin(a) + jitter(rng), 1.5 * ring + jitter(rng)));
    }
  p.F.push_back({4, 3, 2, 1, 0});  // bottom, seen from below
  p.F.push_back({5, 6, 7, 8, 9});  // top
  p.F.push_back({0, 1, 6});        // side 0 as two triangles
  p.F.push_back({0, 6, 5});
  for (int k = 1; k < (open ? 4 : 5); ++k) p.F.push_back({k, (k + 1) % 5, 5 + (k + 1) % 5, 5 + k});
  return p;
}

// OpenSubdiv's evaluation of the polygon mesh itself (Bfr, no refinement), with LimitSurface's
// default boundary rules and the deepest approximation of irregular patches.
class PolygonLimit {
 public:
  explicit PolygonLimit(const PolyData& p) : p_(p) {
    for (const auto& f : p.F) {
      sizes_.push_back(int(f.size()));
      verts_.insert(verts_.end(), f.begin(), f.end());
    }
    osd::Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    osd::Far::TopologyDescriptor desc;
    desc.numVertices = int(p.V.size());
    desc.numFaces = int(p.F.size());
    desc.numVertsPerFace = sizes_.data();
    desc.vertIndicesPerFace = verts_.data();
    using Factory = osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>;
    refiner_.reset(Factory::Create(desc, Factory::Options(osd::Sdc::SCHEME_CATMARK, sdc)));
    osd::Bfr::RefinerSurfaceFactory<>::Options opt;
    opt.SetApproxLevelSmooth(10).SetApproxLevelSharp(10);
    factory_ = std::make_unique<osd::Bfr::RefinerSurfaceFactory<>>(*refiner_, opt);
  }
  // The limit at a point of face f's sub-face k (the quad of corner k, edge k's midpoint, the
  // centre and edge k-1's midpoint), at its normalized coordinates (s, t) (Ptex's): s along edge
  // k, t along edge k-1. A quad's sub-faces are its quarters.
  Vec3 At(int f, int k, double s, double t) const {
    osd::Bfr::Surface<double> surface;
    factory_->InitVertexSurface(f, &surface);
    std::vector<double> pts(size_t(surface.GetNumPatchPoints()) * 3);
    std::vector<double> ctrl;
    for (const Vec3& v : p_.V) ctrl.insert(ctrl.end(), {v.x(), v.y(), v.z()});
    surface.PreparePatchPoints(ctrl.data(), 3, pts.data(), 3);
    const osd::Bfr::Parameterization param = surface.GetParameterization();
    double uv[2];
    if (param.HasSubFaces()) {
      const double st[2] = {s, t};
      param.ConvertNormalizedSubFaceToCoord(k, st, uv);
    } else {  // a quad: the quarter at corner k, bilinear in its corners' (u, v)
      const int n = int(p_.F[f].size());
      std::array<std::array<double, 2>, 4> c;
      param.GetVertexCoord(k, c[0].data());
      param.GetVertexCoord((k + 1) % n, c[1].data());
      param.GetCenterCoord(c[2].data());
      param.GetVertexCoord((k + n - 1) % n, c[3].data());
      for (int i = 0; i < 2; ++i) {
        const double mid1 = 0.5 * (c[0][i] + c[1][i]), mid3 = 0.5 * (c[0][i] + c[3][i]);
        uv[i] = (1 - s) * (1 - t) * c[0][i] + s * (1 - t) * mid1 + s * t * c[2][i] + (1 - s) * t * mid3;
      }
    }
    double P[3];
    surface.Evaluate(uv, pts.data(), 3, P);
    return Vec3(P[0], P[1], P[2]);
  }

 private:
  const PolyData& p_;
  std::vector<int> sizes_, verts_;
  std::unique_ptr<osd::Far::TopologyRefiner> refiner_;
  std::unique_ptr<osd::Bfr::RefinerSurfaceFactory<>> factory_;
};

// Number of distinct undirected edges.
int EdgeCount(const PolyData& p) {
  std::set<std::pair<int, int>> e;
  for (const auto& f : p.F)
    for (size_t k = 0; k < f.size(); ++k) e.insert(std::minmax(f[k], f[(k + 1) % f.size()]));
  return int(e.size());
}

void ExpectSameLimit(const PolyData& p) {
  QuadData q;
  ASSERT_EQ(vcgext::SubdivideOnce(p, q), "");
  int corners = 0;
  for (const auto& f : p.F) corners += int(f.size());
  ASSERT_EQ(int(q.F.size()), corners);  // one quad per corner of every polygon
  ASSERT_EQ(q.V.size(), p.V.size() + size_t(EdgeCount(p)) + p.F.size());
  vcgext::LimitSurfaceOptions opt;
  opt.approxLevelSmooth = opt.approxLevelSharp = 10;
  const auto quads = vcgext::LimitSurface::FromQuads(q, opt);
  ASSERT_TRUE(quads.Ok()) << quads.Error();
  const PolygonLimit reference(p);
  const double size = vcgext::BBoxDiagonal(p.V);
  double worst = 0;
  int child = 0;
  for (int f = 0; f < int(p.F.size()); ++f)
    for (int k = 0; k < int(p.F[f].size()); ++k, ++child) {
      // Far orders a face's children by corner; the child's corner j0 is the parent's corner k
      // (Far numbers the children of vertices first, in the parent's order).
      const auto& c = q.F[child];
      const int j0 = int(std::find(c.begin(), c.end(), p.F[f][k]) - c.begin());
      ASSERT_LT(j0, 4) << "face " << f << " corner " << k;
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j) {
          const double s = 0.25 * i, t = 0.25 * j;  // sub-face coordinates: s along edge k
          // the child's own (u, v): its corner j0 is the sub-face's origin, corner j0 + 1 the
          // midpoint of edge k (counter-clockwise, as the parent)
          double u = s, v = t;
          if (j0 == 1) u = 1 - t, v = s;
          if (j0 == 2) u = 1 - s, v = 1 - t;
          if (j0 == 3) u = t, v = 1 - s;
          Vec3 mine;
          ASSERT_TRUE(quads.Evaluate(child, u, v, q.V, &mine));
          worst = std::max(worst, (mine - reference.At(f, k, s, t)).norm() / size);
        }
    }
  // Both sides are exact B-spline patches away from irregular vertices and Gregory patches in
  // a region of 2^-10 round them: equal to rounding. A midpoint split without the Catmull-Clark
  // rules (the same quads, corners not moved) differs by ~1e-2 of the size.
  EXPECT_LT(worst, 1e-9);
}

TEST(SubdivideOnce, LimitOfTheQuadsIsThePolygonMeshsOwn) {
  ExpectSameLimit(MixedPrism(false));
  ExpectSameLimit(MixedPrism(true));
}

TEST(SubdivideOnce, KeepsTheInputVerticesFirstAndPureQuadsStayQuads) {
  PolyData p = MixedPrism(false);
  QuadData q;
  ASSERT_EQ(vcgext::SubdivideOnce(p, q), "");
  // Vertex i of the output is input vertex i moved by the vertex rule: on a closed mesh it
  // moves inwards (the average of its neighbours' is closer to the centroid).
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& v : p.V) centroid += v / double(p.V.size());
  for (size_t i = 0; i < p.V.size(); ++i) EXPECT_LT((q.V[i] - centroid).norm(), (p.V[i] - centroid).norm()) << i;
  // The output is a valid Catmull-Clark control mesh; subdividing it again as polygons gives
  // four quads per quad.
  PolyData again{q.V, {}};
  for (const auto& f : q.F) again.F.push_back({f[0], f[1], f[2], f[3]});
  QuadData q2;
  ASSERT_EQ(vcgext::SubdivideOnce(again, q2), "");
  EXPECT_EQ(q2.F.size(), 4 * q.F.size());
}

TEST(SubdivideOnce, RefusesWhatTheLimitSurfaceRefuses) {
  PolyData p = MixedPrism(false);
  p.F.push_back({0, 1, 6});  // the triangle again: three faces on edge 0-1, two running it the same way
  QuadData q;
  const std::string err = vcgext::SubdivideOnce(p, q);
  EXPECT_FALSE(err.empty());
  EXPECT_TRUE(q.V.empty() && q.F.empty());
  PolyData big;  // one polygon of 3 000 sides: its face point would have valence 3 000
  for (int k = 0; k < 3000; ++k) big.V.push_back(Vec3(std::cos(k * 2 * M_PI / 3000), std::sin(k * 2 * M_PI / 3000), 0));
  big.F.emplace_back();
  for (int k = 0; k < 3000; ++k) big.F[0].push_back(k);
  EXPECT_NE(vcgext::SubdivideOnce(big, q), "");
}

}  // namespace
