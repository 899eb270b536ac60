// Debris and small holes of a raw scan (vcg_ext/quad/scan_artifacts.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "vcg_ext/quad/scan_artifacts.h"
#include "test_support.h"

using vcgext::QuadData;
using vcgext::Vec3;

namespace {
// A closed box of six quads, size s, corner at o.
void AddBox(QuadData& q, const Vec3& o, double s) {
  const int b = int(q.V.size());
  for (int i = 0; i < 8; ++i) q.V.push_back(o + s * Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& c : f) q.F.push_back({b + c[0], b + c[1], b + c[2], b + c[3]});
}
}  // namespace

// A unit box (diagonal 1.73) with k specks of size 0.01 around it: the specks are counted with
// their patches by a brute count, and warned about only when they hold 2 % of the patches or more.
TEST(ScanArtifacts, SmallPiecesAreCountedAndWarnedAboutWhenTheyCost) {
  QuadData cage;
  AddBox(cage, Vec3::Zero(), 1.0);
  const double diag = std::sqrt(3.0);
  EXPECT_EQ(vcgext::DebrisWarning(cage, diag), "");
  const vcgext::SmallPieces none = vcgext::FindSmallPieces(cage, 0.02 * diag);
  EXPECT_EQ(none.pieces, 1);
  EXPECT_EQ(none.small, 0);
  for (int k = 0; k < 20; ++k) AddBox(cage, Vec3(2 + 0.1 * k, 0, 0), 0.01);
  const vcgext::SmallPieces s = vcgext::FindSmallPieces(cage, 0.02 * diag);
  EXPECT_EQ(s.pieces, 21);
  EXPECT_EQ(s.small, 20);
  EXPECT_EQ(s.smallPatches, 120);
  // measured against the input's diagonal given, not the cage's own
  const std::string w = vcgext::DebrisWarning(cage, diag);
  EXPECT_NE(w.find("20 of the input's 21 separate pieces"), std::string::npos) << w;
  EXPECT_NE(w.find("120 of the cage's 126 patches"), std::string::npos) << w;
  EXPECT_NE(w.find("Remove Isolated pieces (wrt Diameter)"), std::string::npos) << w;
  // a box of side s has s of the unit box's diagonal: 0.019 is small, 0.021 is not
  QuadData two;
  AddBox(two, Vec3::Zero(), 1.0);
  AddBox(two, Vec3(3, 0, 0), 0.019);
  AddBox(two, Vec3(5, 0, 0), 0.021);
  EXPECT_EQ(vcgext::FindSmallPieces(two, 0.02 * diag).small, 1);
  // small pieces below 2 % of the patches: no warning
  QuadData fine;
  AddBox(fine, Vec3::Zero(), 1.0);
  // repeated faces stand for a finer cage of the big piece: only the counts matter here
  for (int k = 0; k < 60; ++k) fine.F.push_back(fine.F[size_t(k % 6)]);  // 66 patches in one piece
  AddBox(fine, Vec3(2, 0, 0), 0.01);                                     // 6 of 72: 8 %
  EXPECT_NE(vcgext::DebrisWarning(fine, diag), "");
  for (int k = 0; k < 300; ++k) fine.F.push_back(fine.F[size_t(k % 6)]);  // 6 of 372: 1.6 %
  EXPECT_EQ(vcgext::DebrisWarning(fine, diag), "");
}

namespace {
// An open n x n grid of unit quads.
QuadData QuadGrid(int n) {
  QuadData g;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) g.V.push_back(Vec3(i, j, 0));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) g.F.push_back({j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i});
  return g;
}
}  // namespace

// Holes counted by their boundary loops (the holes cut), small ones by the loop's size; the
// warning from kManySmallHoles holes smaller than the cage's average patch on, with the patches of
// the cage that border its boundary.
TEST(ScanArtifacts, ManySmallHolesAreCountedAndWarnedAbout) {
  for (int k : {1, 9, 10, 30}) {
    const vcgext::TriData s = testsupport::SphereWithHoles(k);
    EXPECT_EQ(vcgext::FindSmallHoles(s, 0.25).holes, k);
    EXPECT_EQ(vcgext::FindSmallHoles(s, 0.25).small, k);
    EXPECT_EQ(vcgext::FindSmallHoles(s, 0.1).small, 0) << "holes of about 0.15";
  }
  EXPECT_EQ(vcgext::FindSmallHoles(testsupport::Icosphere(2), 1.0).holes, 0);
  // a 3 x 3 grid cage: 9 patches of side sqrt(4 pi / 9) = 1.2 (every hole smaller), 8 of them on
  // its boundary
  EXPECT_EQ(vcgext::HolesWarning(testsupport::SphereWithHoles(9), QuadGrid(3)), "");
  const std::string w = vcgext::HolesWarning(testsupport::SphereWithHoles(10), QuadGrid(3));
  EXPECT_NE(w.find("10 of the input's 10 holes are smaller than the cage's patches"), std::string::npos) << w;
  EXPECT_NE(w.find("8 of whose 9 patches border one"), std::string::npos) << w;
  EXPECT_NE(w.find("Close Holes"), std::string::npos) << w;
  // the parameter that closes them for the layout, at the patches' side (the holed sphere's area
  // 12.4: sqrt(12.4 / 9) = 1.174 of its diagonal 2 sqrt(3): 33.9 %)
  EXPECT_NE(w.find("(closeHoles) at 33.9 %"), std::string::npos) << w;
  // 3 600 patches of side 0.06: the holes are larger than the patches, no warning
  EXPECT_EQ(vcgext::HolesWarning(testsupport::SphereWithHoles(30), QuadGrid(60)), "");
  // outlines are not holes: a sheet's rim, and 12 small flaps beside a closed sphere (what the
  // working copy makes of flaps standing on edges of three triangles) or beside the holed one
  EXPECT_EQ(vcgext::FindSmallHoles(testsupport::PlaneGrid(8, 8), 1.0).holes, 0);
  vcgext::TriData flaps = testsupport::Icosphere(3), holedFlaps = testsupport::SphereWithHoles(10);
  for (vcgext::TriData* t : {&flaps, &holedFlaps})
    for (int k = 0; k < 12; ++k) {
      const int n = int(t->V.size());
      const Vec3 c(1.2 + 0.1 * k, 0, 0);
      t->V.insert(t->V.end(), {c, c + Vec3(0.05, 0, 0), c + Vec3(0.05, 0, 0.05), c + Vec3(0, 0, 0.05)});
      t->F.push_back({n, n + 1, n + 2});
      t->F.push_back({n, n + 2, n + 3});
    }
  EXPECT_EQ(vcgext::FindSmallHoles(flaps, 0.25).holes, 0);
  EXPECT_EQ(vcgext::HolesWarning(flaps, QuadGrid(3)), "");
  EXPECT_EQ(vcgext::FindSmallHoles(holedFlaps, 0.25).holes, 10);
  EXPECT_EQ(vcgext::FindSmallHoles(holedFlaps, 0.25).small, 10);
  // a closed cage has no hole to border: no warning, whatever the input
  QuadData box;
  AddBox(box, Vec3::Zero(), 1.0);
  EXPECT_EQ(vcgext::HolesWarning(testsupport::SphereWithHoles(30), box), "");
}

namespace {
vcgext::TriData Merged(vcgext::TriData a, const vcgext::TriData& b) {
  const int n = int(a.V.size());
  a.V.insert(a.V.end(), b.V.begin(), b.V.end());
  for (auto f : b.F) a.F.push_back({f[0] + n, f[1] + n, f[2] + n});
  return a;
}
}  // namespace

// A doubled wall: two nested icospheres 0.2 % of the radius apart (the corpus's scan_double.off)
// face the same way everywhere; a single sphere, a thin closed plate 0.01 thick (its two sides
// face each other), two intersecting spheres and a sphere inside another at half its radius (50
// times the reach) do not. Brute check of the area share: every triangle's centroid of the inner
// sphere sees the outer one.
TEST(ScanArtifacts, DoubledWallIsFoundAndWarnedAbout) {
  using vcgext::TriData;
  const TriData s = testsupport::Icosphere(4);
  const TriData doubled = Merged(s, testsupport::Icosphere(4, 1.002));
  const vcgext::EmbreeScene ds(doubled);
  const vcgext::SecondSheets w = vcgext::FindSecondSheets(doubled, ds);
  EXPECT_GT(w.doubled.areaPercent, 99.9);
  EXPECT_GT(w.doubled.medianDistance, 0.0015);  // 0.002 between the spheres, their facets 2e-3 flatter
  EXPECT_LT(w.doubled.medianDistance, 0.003);
  QuadData cage;
  AddBox(cage, Vec3::Zero(), 1.0);
  const std::string msg = vcgext::DoubledWallWarning(w, cage);
  EXPECT_NE(msg.find("100 % of the input's area has a second sheet facing the same way"), std::string::npos) << msg;
  EXPECT_NE(msg.find("the cage has 6"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Screened Poisson"), std::string::npos) << msg;

  TriData plate = s, apart = Merged(s, testsupport::Icosphere(4)), inside = Merged(s, testsupport::Icosphere(4, 0.5));
  for (auto& v : plate.V) v.z() *= 0.005;
  for (size_t i = s.V.size(); i < apart.V.size(); ++i) apart.V[i].x() += 1.5;
  for (const TriData* t : std::vector<const TriData*>{&s, &plate, &apart, &inside}) {
    const vcgext::EmbreeScene sc(*t);
    const vcgext::SecondSheets st = vcgext::FindSecondSheets(*t, sc);
    EXPECT_EQ(st.doubled.areaPercent, 0.0);
    EXPECT_EQ(vcgext::DoubledWallWarning(st, cage), "");
  }
  // a copy of a quarter of the sphere (a region scanned twice): about a fifth of the area
  TriData cap;
  cap.V = testsupport::Icosphere(4, 1.002).V;
  for (const auto& f : s.F)
    if (s.V[size_t(f[0])].z() > 0.5) cap.F.push_back(f);
  const TriData part = Merged(s, cap);
  const vcgext::EmbreeScene ps(part);
  const double capShare = 100.0 * double(2 * cap.F.size()) / double(part.F.size());
  const vcgext::SecondSheets pw = vcgext::FindSecondSheets(part, ps);
  EXPECT_NEAR(pw.doubled.areaPercent, capShare, 2.0);
  EXPECT_NE(vcgext::DoubledWallWarning(pw, cage), "");
}

// A thin part: a sphere squashed to a plate 0.01 thick (diagonal 2.83, reach 0.028) is a thin
// sheet over nearly all its area, with either orientation (the signed volume says which side is
// inside), its median thickness between the rim's and the centre's 0.01; the sphere is not, and
// neither are two thick boxes 0.005 apart (their facing sides see each other from outside: a gap,
// not a sheet). The warning follows the share.
TEST(ScanArtifacts, ThinSheetIsFoundFromItsInsideAndWarnedAbout) {
  using vcgext::TriData;
  const TriData s = testsupport::Icosphere(4);
  TriData plate = s;
  for (auto& v : plate.V) v.z() *= 0.005;
  TriData reversed = plate;
  for (auto& f : reversed.F) std::swap(f[1], f[2]);
  QuadData cage;
  AddBox(cage, Vec3::Zero(), 1.0);
  for (const TriData* t : {&plate, &reversed}) {
    const vcgext::EmbreeScene sc(*t);
    const vcgext::SecondSheets w = vcgext::FindSecondSheets(*t, sc);
    EXPECT_GT(w.thin.areaPercent, 90.0);
    EXPECT_GT(w.thin.medianDistance, 0.004);
    EXPECT_LE(w.thin.medianDistance, 0.0101);
    EXPECT_EQ(w.doubled.areaPercent, 0.0);
    const std::string msg = vcgext::ThinSheetWarning(w, cage);
    EXPECT_NE(msg.find("of the input's area is a thin sheet"), std::string::npos) << msg;
    EXPECT_NE(msg.find("the cage has 6 patches"), std::string::npos) << msg;
    EXPECT_NE(msg.find("Target patches"), std::string::npos) << msg;
  }
  QuadData boxes;
  AddBox(boxes, Vec3::Zero(), 1.0);
  AddBox(boxes, Vec3(1.005, 0, 0), 1.0);
  for (const TriData& t : {s, vcgext::SplitQuads(boxes)}) {
    const vcgext::EmbreeScene sc(t);
    const vcgext::SecondSheets w = vcgext::FindSecondSheets(t, sc);
    EXPECT_EQ(w.thin.areaPercent, 0.0);
    EXPECT_EQ(vcgext::ThinSheetWarning(w, cage), "");
  }
}
