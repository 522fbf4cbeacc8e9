// Lattice builders (seed 001's box, seed 000's sheet and semi-sphere) and
// the checks that name a bad lattice's element.
#include <algorithm>
#include <cmath>
#include <vector>

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

// One bending spring per inner edge, across it, at its rest length; none
// on the border.
TEST(MassspringLattice, BendingSpringsSpanEachInnerEdge) {
  Lattice pair = make_sheet(2, 2, 0.01, {});
  const std::vector<Eigen::Vector3i> two{{0, 1, 3}, {0, 3, 2}};
  const std::size_t before = pair.springs.size();
  EXPECT_EQ(add_bending(pair, two, 5, 0.1), 1);
  ASSERT_EQ(pair.springs.size(), before + 1);
  const Spring& s = pair.springs.back();
  EXPECT_EQ(std::minmax(s.i, s.j), std::minmax(1, 2));
  EXPECT_NEAR(s.rest, std::sqrt(2) * 0.01, 1e-15);
  EXPECT_EQ(s.k, 5);
  EXPECT_EQ(s.b, 0.1);
  const int rings = 4, segments = 12;
  Lattice dome = make_semisphere(rings, segments, 0.05, {});
  std::vector<Eigen::Vector3i> faces;
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      const int a = r * segments + k, b = r * segments + (k + 1) % segments;
      if (r + 1 < rings) {
        faces.emplace_back(a, b, b + segments);
        faces.emplace_back(a, b + segments, a + segments);
      } else {
        faces.emplace_back(a, b, rings * segments);
      }
    }
  // Edges: 3 per face, shared pairwise but for the base ring's.
  EXPECT_EQ(add_bending(dome, faces, 1, 0), (3 * int(faces.size()) - segments) / 2);
  EXPECT_NO_THROW(check(dome));
  EXPECT_THROW(add_bending(dome, {{0, 1, 999}}, 1, 0), std::invalid_argument);
  EXPECT_THROW(add_bending(dome, faces, -1, 0), std::invalid_argument);
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
