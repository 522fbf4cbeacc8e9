// The S-Chain haptic model (001 eq 1): release returns to rest, force grows
// with depth, the stiffer side pushes back harder, links hold after every
// tick, cost follows the moved chains, and bad or extreme input is handled.
#include <gtest/gtest.h>

#include "models/deformable/schain.h"

namespace hcosim::models::deformable {
namespace {

constexpr double kTick = 1e-3;

// 10 x 10 x 10 chains 1 cm apart (seed scale), floor anchored.
ChainLattice chain_cube(int n = 10, ChainMaterial m = {}) {
  ChainLattice l = make_chain_box(n, n, n, 0.01, m);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) l.anchored[l.index(i, j, 0)] = 1;
  return l;
}

int top_centre(const ChainLattice& l) { return l.index(l.nx / 2, l.ny / 2, l.nz - 1); }

// Presses `e` down by `depth` for `ticks` ticks; returns the force.
Eigen::Vector3d press(SChain& s, int e, double depth, int ticks = 200) {
  const Eigen::Vector3d target = s.lattice().rest(e) - Eigen::Vector3d(0, 0, depth);
  for (int k = 0; k < ticks; ++k) s.tick(kTick, e, target);
  return s.force();
}

// Every link between neighbours is inside its allowed box.
void expect_links_hold(const SChain& s) {
  const ChainLattice& l = s.lattice();
  const int stride[3] = {1, l.nx, l.nx * l.ny};
  for (int k = 0; k < l.nz; ++k)
    for (int j = 0; j < l.ny; ++j)
      for (int i = 0; i < l.nx; ++i) {
        const int e = l.index(i, j, k), at[3] = {i, j, k}, dims[3] = {l.nx, l.ny, l.nz};
        for (int axis = 0; axis < 3; ++axis) {
          if (at[axis] + 1 >= dims[axis]) continue;
          const int n = e + stride[axis];
          const ChainMaterial &a = l.material[e], &b = l.material[n];
          const Eigen::Vector3d d = s.displacement(n) - s.displacement(e);
          const double tol = 1e-7 * l.spacing;
          for (int c = 0; c < 3; ++c) {
            if (c == axis) {
              EXPECT_LE(d[c], std::min(a.stretch, b.stretch) * l.spacing + tol);
              EXPECT_GE(d[c], -std::min(a.compress, b.compress) * l.spacing - tol);
            } else {
              EXPECT_LE(std::abs(d[c]), std::min(a.shear, b.shear) * l.spacing + tol);
            }
          }
        }
      }
}

TEST(SChain, ReleaseReturnsExactlyToRest) {
  SChain s(chain_cube());
  const int e = top_centre(s.lattice());
  EXPECT_GT(press(s, e, 0.005).z(), 0);  // pushes the stylus back out
  EXPECT_GT(s.moved().size(), 1u);
  for (int k = 0; k < 2000; ++k) s.tick(kTick, -1, {});
  EXPECT_TRUE(s.moved().empty());
  EXPECT_EQ(s.force(), Eigen::Vector3d::Zero());
  for (int i = 0; i < s.lattice().size(); ++i) EXPECT_EQ(s.displacement(i), Eigen::Vector3d::Zero());
}

// Past 4.5 mm the column under the contact is fully compressed against the
// anchored floor (9 links of 0.5 mm): the chains stop and the limit
// stiffness takes over, so the force still grows.
TEST(SChain, ForceGrowsMonotonicallyWithDepth) {
  SChain s(chain_cube());
  const int e = top_centre(s.lattice());
  double last = 0;
  for (int step = 1; step <= 16; ++step) {
    const Eigen::Vector3d f = press(s, e, 0.0005 * step);
    SCOPED_TRACE("depth " + std::to_string(0.5 * step) + " mm");
    EXPECT_GT(f.z(), last);
    EXPECT_NEAR(f.x(), 0, 1e-12);
    EXPECT_NEAR(f.y(), 0, 1e-12);
    last = f.z();
    expect_links_hold(s);
  }
}

// 001 Fig 8: left half four times stiffer, with a range half as wide.
TEST(SChain, StifferSidePushesBackHarderAndDeformsLess) {
  ChainLattice l = chain_cube();
  for (int e = 0; e < l.size(); ++e)
    if (e % l.nx < l.nx / 2) l.material[e] = {8, 0.025, 0.025, 0.025};
  const int stiff = l.index(2, 5, 9), soft = l.index(7, 5, 9);
  SChain a(l), b(l);
  const Eigen::Vector3d fa = press(a, stiff, 0.003), fb = press(b, soft, 0.003);
  EXPECT_GT(fa.z(), 2 * fb.z());
  // Less deformation at the contact: its neighbours follow it more closely.
  const double dent_stiff = (a.displacement(stiff) - a.displacement(l.index(2, 6, 9))).norm();
  const double dent_soft = (b.displacement(soft) - b.displacement(l.index(7, 6, 9))).norm();
  EXPECT_LT(dent_stiff, dent_soft);
  expect_links_hold(a);
  expect_links_hold(b);
}

// The same press moves the same chains in a 10^3 and a 40^3 lattice: the
// cost follows the moved chains, not the lattice.
TEST(SChain, MovedChainsDoNotDependOnLatticeSize) {
  SChain small(chain_cube(10)), large(chain_cube(40));
  const int es = small.lattice().index(5, 5, 9), el = large.lattice().index(20, 20, 39);
  int ms = 0, ml = 0;
  for (int k = 0; k < 50; ++k) {
    ms = small.tick(kTick, es, small.lattice().rest(es) - Eigen::Vector3d(0, 0, 0.002));
    ml = large.tick(kTick, el, large.lattice().rest(el) - Eigen::Vector3d(0, 0, 0.002));
  }
  EXPECT_GT(ms, 1);
  EXPECT_EQ(ms, ml);
  EXPECT_LT(large.moved().size(), 0.01 * large.lattice().size());
}

// An L of chains (the +x, +y quarter of a 10 x 10 x 4 slab missing, floor
// anchored), as a body that is not a box has: a press on one arm moves no
// missing element and no element across the gap, and a point over the gap
// touches the nearest element that is on the surface.
TEST(SChain, ChainsThatAreNotThereAreNeitherMovedNorTouched) {
  ChainLattice l = make_chain_box(10, 10, 4, 0.01, {});
  auto missing = [](int i, int j) { return i >= 5 && j >= 5; };
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i) {
        l.present[l.index(i, j, k)] = !missing(i, j);
        l.anchored[l.index(i, j, k)] = k == 0 && !missing(i, j);
      }
  SChain s(l);
  const int e = l.index(7, 2, 3);  // on the +x arm, at the top
  EXPECT_GT(press(s, e, 0.008).z(), 0);
  EXPECT_GT(s.moved().size(), 10u);
  for (const int m : s.moved()) {
    EXPECT_TRUE(l.present[m]) << "element " << m << " is not there but moved";
  }
  // Inside the gap, just by the +x arm's inner face at j = 4.
  const int near = s.nearest_surface(l.rest(l.index(7, 5, 2)) + Eigen::Vector3d(0, 0.002, 0));
  EXPECT_EQ(near, l.index(7, 4, 2));
  EXPECT_THROW(s.tick(kTick, l.index(7, 7, 3), l.rest(l.index(7, 7, 3))), std::invalid_argument);
}

TEST(SChain, FarNanAndLongHeldContactsAreHandled) {
  SChain s(chain_cube());
  const int e = top_centre(s.lattice());
  EXPECT_THROW(s.tick(kTick, s.lattice().size(), {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(s.tick(kTick, e, {NAN, 0, 0}), std::invalid_argument);
  EXPECT_THROW(s.tick(0, -1, {}), std::invalid_argument);
  EXPECT_EQ(s.nearest_surface({NAN, 0, 0}), -1);
  EXPECT_EQ(s.nearest_surface({1, 1, 1}), -1);  // a metre away
  EXPECT_EQ(s.nearest_surface(s.lattice().rest(e) + Eigen::Vector3d(0, 0, 0.003)), e);
  EXPECT_EQ(s.nearest_surface(s.lattice().rest(s.lattice().index(5, 5, 5)) + Eigen::Vector3d(0.001, 0, 0.035)), e);
  // A point dragged 10 cm through the object stays finite.
  EXPECT_TRUE(press(s, e, 0.1, 50).allFinite());
  // Held inside for a minute of haptic ticks: a steady force, links holding.
  const Eigen::Vector3d f1 = press(s, e, 0.004, 1000), f60 = press(s, e, 0.004, 59000);
  EXPECT_NEAR(f60.z(), f1.z(), 1e-9);
  expect_links_hold(s);
}

}  // namespace
}  // namespace hcosim::models::deformable
