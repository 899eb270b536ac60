// Small separate pieces of a cage (vcg_ext/quad/debris.h).
#include <gtest/gtest.h>

#include <cmath>

#include "vcg_ext/quad/debris.h"

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
TEST(Debris, SmallPiecesAreCountedAndWarnedAboutWhenTheyCost) {
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
