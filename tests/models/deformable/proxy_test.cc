// The proxy's geometry on a mesh, against brute force and the analytic
// plane: the nearest point of a triangle, where a path goes in (and only
// inward), the walk over faces, and the smooth normal across a crease.
#include "models/deformable/proxy.h"

#include <algorithm>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace hcosim::models::deformable {
namespace {

// A 4 x 4 grid of unit squares in z = 0, two triangles each, facing +z.
struct Grid {
  Eigen::Matrix3Xd x{3, 25};
  std::vector<Eigen::Vector3i> triangles;
  Grid() {
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) x.col(i + 5 * j) << i, j, 0;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const int a = i + 5 * j;
        triangles.emplace_back(a, a + 1, a + 6);
        triangles.emplace_back(a, a + 6, a + 5);
      }
  }
};

Eigen::Vector3d at(const Eigen::Matrix3Xd& x, const MeshProxy& m, const SurfacePoint& p) {
  const Eigen::Vector3i& t = m.triangle(p.face);
  return p.bary[0] * x.col(t[0]) + p.bary[1] * x.col(t[1]) + p.bary[2] * x.col(t[2]);
}

TEST(MeshProxy, NearestOnATriangleIsNoFartherThanAnyPointOfIt) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0.2), c(0.3, 0.9, -0.1);
  for (int n = 0; n < 200; ++n) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const Eigen::Vector3d w = nearest_on_triangle(p, a, b, c);
    EXPECT_NEAR(w.sum(), 1, 1e-12);
    EXPECT_GE(w.minCoeff(), -1e-12);
    const double d = (w[0] * a + w[1] * b + w[2] * c - p).norm();
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; i + j <= 20; ++j) {
        const Eigen::Vector3d q = a + (b - a) * (i / 20.0) + (c - a) * (j / 20.0);
        ASSERT_LE(d, (q - p).norm() + 1e-12) << p.transpose();
      }
  }
}

TEST(MeshProxy, APathGoesInWhereItCrossesAndOnlyInward) {
  const Grid g;
  const MeshProxy m(g.triangles, 25);
  const SurfacePoint p = m.entry(g.x, {1.3, 2.6, 1}, {1.5, 2.2, -1});
  ASSERT_GE(p.face, 0);
  EXPECT_LT((at(g.x, m, p) - Eigen::Vector3d(1.4, 2.4, 0)).norm(), 1e-12);
  EXPECT_EQ(m.normal(g.x, p.face), Eigen::Vector3d::UnitZ());
  EXPECT_EQ(m.entry(g.x, {1.5, 2.2, -1}, {1.3, 2.6, 1}).face, -1);   // outward
  EXPECT_EQ(m.entry(g.x, {1.3, 2.6, 1}, {1.3, 2.6, 0.5}).face, -1);  // not there yet
  EXPECT_EQ(m.entry(g.x, {5.3, 2.6, 1}, {5.3, 2.6, -1}).face, -1);   // beside the mesh
  // Through a shared vertex: one face takes it.
  EXPECT_GE(m.entry(g.x, {2, 2, 1}, {2, 2, -1}).face, 0);
}

TEST(MeshProxy, TheWalkFindsTheNearestPointFacesAway) {
  const Grid g;
  const MeshProxy m(g.triangles, 25);
  const SurfacePoint start = m.entry(g.x, {0.2, 0.1, 1}, {0.2, 0.1, -1});
  for (const Eigen::Vector3d& q :
       {Eigen::Vector3d(3.7, 3.1, 0.4), Eigen::Vector3d(2.5, 0.5, -0.3), Eigen::Vector3d(9, 9, 0)}) {
    const SurfacePoint p = m.nearest(g.x, start, q);
    const Eigen::Vector3d expect(std::clamp(q.x(), 0.0, 4.0), std::clamp(q.y(), 0.0, 4.0), 0);
    EXPECT_LT((at(g.x, m, p) - expect).norm(), 1e-12) << q.transpose();
  }
}

TEST(MeshProxy, TheClosestPointAmongAllFacesAndWhichSideItIsOn) {
  const Grid g;
  const MeshProxy m(g.triangles, 25);
  const SurfacePoint p = m.closest(g.x, {3.3, 0.6, -0.2});
  EXPECT_LT((m.point(g.x, p) - Eigen::Vector3d(3.3, 0.6, 0)).norm(), 1e-12);
  EXPECT_TRUE(m.behind(g.x, p, {3.3, 0.6, -0.2}));
  EXPECT_FALSE(m.behind(g.x, m.closest(g.x, {3.3, 0.6, 0.2}), {3.3, 0.6, 0.2}));
}

TEST(MeshProxy, TheSmoothNormalIsOneAcrossACrease) {
  // Two faces folded along the edge x = 1 by 90 degrees: a roof.
  Eigen::Matrix3Xd x(3, 4);
  x << 0, 1, 1, 2,  //
      0, 0, 1, 0,   //
      0, 1, 1, 0;
  const std::vector<Eigen::Vector3i> roof{{0, 1, 2}, {1, 3, 2}};
  const MeshProxy m(roof, 4);
  const Eigen::Vector3d left = m.normal(x, 0), right = m.normal(x, 1);
  EXPECT_NEAR(left.dot(right), 0, 1e-12);
  // On the ridge, from either face, the same normal: halfway between.
  const Eigen::Vector3d a = m.normal(x, SurfacePoint{0, {0, 0.5, 0.5}});
  const Eigen::Vector3d b = m.normal(x, SurfacePoint{1, {0.5, 0, 0.5}});
  EXPECT_LT((a - b).norm(), 1e-12);
  EXPECT_LT((a - (left + right).normalized()).norm(), 1e-12);
  EXPECT_LT((m.point(x, SurfacePoint{0, {0, 0.5, 0.5}}) - Eigen::Vector3d(1, 0.5, 1)).norm(), 1e-12);
}

// The grid's candidates hold every face a box meets: entry among them is
// entry among all.
TEST(FaceGrid, ItsCandidatesHoldEveryFaceABoxMeets) {
  const Grid g;
  const MeshProxy m(g.triangles, 25);
  const FaceGrid grid(g.x, g.triangles, 0.7, 1e-9);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 4.5), z(-1, 1);
  for (int n = 0; n < 300; ++n) {
    const Eigen::Vector3d from(u(rng), u(rng), std::abs(z(rng))), to(u(rng), u(rng), -std::abs(z(rng)));
    Eigen::AlignedBox3d box(from);
    box.extend(to);
    std::vector<int> near;
    grid.near(box, near);
    const SurfacePoint all = m.entry(g.x, from, to), some = m.entry(g.x, from, to, &near);
    ASSERT_EQ(all.face, some.face) << from.transpose() << " to " << to.transpose();
  }
  std::vector<int> none{7};
  grid.near(Eigen::AlignedBox3d(Eigen::Vector3d(9, 9, 9), Eigen::Vector3d(10, 10, 10)), none);
  EXPECT_TRUE(none.empty());
  EXPECT_THROW(FaceGrid(g.x, g.triangles, 0, 0), std::invalid_argument);
}

TEST(MeshProxy, RefusesABadMesh) {
  const Grid g;
  EXPECT_THROW(MeshProxy(g.triangles, 24), std::invalid_argument);
  EXPECT_THROW(MeshProxy({}, 25), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::deformable
