// Lattice builders (seed 001's box, seed 000's sheet and semi-sphere) and
// the checks that name a bad lattice's element.
#include <cmath>

#include <gtest/gtest.h>

#include "models/massspring/lattice.h"
#include "tests/support/temp_dir.h"

namespace hcosim::models::massspring {
namespace {

TEST(MassspringLattice, BoxOfSeed001Figure7) {
  const Lattice one = make_box(10, 10, 10, 0.01, {});
  EXPECT_EQ(one.size(), 1000);
  EXPECT_EQ(one.springs.size(), 2700u + 2430u);  // structural + one diagonal per face square
  EXPECT_EQ(make_box(10, 10, 10, 0.01, {}, Shear::both).springs.size(), 2700u + 4860u);
  for (const Spring& s : one.springs) EXPECT_NEAR(s.rest, (one.rest.col(s.i) - one.rest.col(s.j)).norm(), 1e-15);
  EXPECT_NO_THROW(check(one));
}

TEST(MassspringLattice, SheetAndSemiSphereOfSeed000Figure7) {
  const Lattice sheet = make_sheet(5, 4, 0.01, {});
  EXPECT_EQ(sheet.size(), 20);
  EXPECT_EQ(sheet.springs.size(), 4u * 4 + 5u * 3 + 2u * 4 * 3);
  EXPECT_EQ(std::count(sheet.anchored.begin(), sheet.anchored.end(), 1), 14);  // the frame
  const Lattice dome = make_semisphere(4, 12, 0.05, {});
  EXPECT_EQ(dome.size(), 4 * 12 + 1);
  EXPECT_EQ(std::count(dome.anchored.begin(), dome.anchored.end(), 1), 12);  // the base ring
  for (int i = 0; i < dome.size(); ++i) {
    EXPECT_NEAR(dome.rest.col(i).norm(), 0.05, 1e-12);
    EXPECT_GE(dome.rest(2, i), -1e-12);
  }
  EXPECT_NO_THROW(check(dome));
}

TEST(MassspringLattice, BadLatticesNameTheElement) {
  Lattice l = make_box(2, 2, 2, 0.01, {});
  l.mass[3] = 0;
  EXPECT_NE(tests::message_of([&] { check(l); }).find("mass 3"), std::string::npos);
  l = make_box(2, 2, 2, 0.01, {});
  l.springs[4].j = 99;
  EXPECT_NE(tests::message_of([&] { check(l); }).find("spring 4"), std::string::npos);
  l = make_box(2, 2, 2, 0.01, {});
  l.springs[2].k = NAN;
  EXPECT_NE(tests::message_of([&] { check(l); }).find("spring 2"), std::string::npos);
  EXPECT_NE(tests::message_of([] { make_box(1, 2, 2, 0.01, {}); }).find("2 x 2 x 2"), std::string::npos);
  EXPECT_NE(tests::message_of([] { make_sheet(3, 3, -1, {}); }).find("spacing"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::models::massspring
