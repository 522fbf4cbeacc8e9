// Quartets. Bending hinges: the signed dihedral angle and its gradient
// against finite differences, the invariances that make their forces
// conserve momentum, the hinges of a mesh, and the implicit matrix's
// stiffness at rest. Volume floors: the signed volume and its gradient,
// a floor that acts below its rest only, and the tetrahedra of a box.
#include "models/massspring/quartet.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "models/massspring/forces.h"
#include "tests/support/temp_dir.h"

namespace hcosim::models::massspring {
namespace {

// Two triangles over the edge from (0,0,0) to (1,0,0): corner k at +y,
// corner l at -y lifted by `lift` along z and shifted along the edge.
Lattice wing(double lift, double shift = 0.3) {
  Lattice l;
  l.rest.resize(3, 4);
  l.rest << 0, 1, 0.4, shift, 0, 0, 1, -1, 0, 0, 0.2, lift;
  l.mass.setConstant(4, 1e-3);
  l.anchored.assign(4, 0);
  l.quartets.push_back({0, 1, 2, 3, 0, 1, 0});
  return l;
}

TEST(MassspringHinge, FlatIsZeroAndEachFoldHasItsSign) {
  Eigen::Vector3d g[4];
  Lattice l = wing(0);
  l.rest(2, 2) = 0;
  EXPECT_NEAR(dihedral(l.quartets[0], l.rest, g), 0, 1e-15);
  const double up = dihedral(l.quartets[0], wing(0.5).rest, g), down = dihedral(l.quartets[0], wing(-0.5).rest, g);
  EXPECT_GT(std::abs(up), 0.1);
  EXPECT_NEAR(up + down, 2 * dihedral(l.quartets[0], wing(0).rest, g), 1e-12);  // mirror images about k's tilt
  EXPECT_LT(up * down, 0);
}

TEST(MassspringHinge, GradientIsTheAngleFiniteDifference) {
  for (const double lift : {-1.5, -0.3, 0.0, 0.4, 2.0}) {
    const Lattice l = wing(lift, lift > 0 ? 1.4 : -0.2);  // l projecting beyond the edge too
    Eigen::Vector3d g[4], unused[4];
    dihedral(l.quartets[0], l.rest, g);
    const double eps = 1e-7;
    for (int c = 0; c < 4; ++c)
      for (int a = 0; a < 3; ++a) {
        Eigen::Matrix3Xd xp = l.rest, xm = l.rest;
        xp(a, c) += eps, xm(a, c) -= eps;
        const double fd = (dihedral(l.quartets[0], xp, unused) - dihedral(l.quartets[0], xm, unused)) / (2 * eps);
        EXPECT_NEAR(g[c][a], fd, 1e-6) << "lift " << lift << " corner " << c << " axis " << a;
      }
  }
}

TEST(MassspringHinge, ForcesHaveNoNetForceOrMomentAndAreMinusTheEnergyGradient) {
  Lattice l = wing(0.3);
  l.quartets[0].rest = -0.2;
  l.quartets[0].b = 0.01;
  Eigen::Matrix3Xd x = l.rest, v(3, 4);
  v << 0.1, -0.2, 0.3, 0.05, 0.2, 0.1, -0.1, 0.3, -0.3, 0.2, 0.1, -0.1;
  Eigen::Vector3d f[4];
  quartet_forces(l.quartets[0], x, v, f);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  for (int c = 0; c < 4; ++c) sum += f[c], moment += x.col(c).cross(f[c]);
  EXPECT_LT(sum.norm(), 1e-12);
  EXPECT_LT(moment.norm(), 1e-12);
  // Without the damper, the force is minus the energy's gradient.
  l.quartets[0].b = 0;
  quartet_forces(l.quartets[0], x, v, f);
  const double eps = 1e-7;
  for (int c = 0; c < 4; ++c)
    for (int a = 0; a < 3; ++a) {
      Eigen::Matrix3Xd xp = x, xm = x;
      xp(a, c) += eps, xm(a, c) -= eps;
      const double de = (quartet_energy(l.quartets[0], xp) - quartet_energy(l.quartets[0], xm)) / (2 * eps);
      EXPECT_NEAR(f[c][a], -de, 1e-6);
    }
}

TEST(MassspringHinge, ImplicitMatrixAtRestIsTheForceJacobian) {
  // At the rest angle the dropped curvature term is zero: k g g^T is exact.
  Lattice l = wing(0.3);
  Eigen::Vector3d g[4];
  l.quartets[0].rest = dihedral(l.quartets[0], l.rest, g);
  l.quartets[0].stiffness = 0.7, l.quartets[0].b = 0.05;
  const std::vector<int> masses{0, 1, 2, 3}, slot{0, 1, 2, 3}, hinges{0};
  const Eigen::MatrixXd M = Eigen::MatrixXd(implicit_matrix(l, {}, {}, masses, slot, l.rest, 0.0));
  const Eigen::MatrixXd A1 = Eigen::MatrixXd(implicit_matrix(l, {}, hinges, masses, slot, l.rest, 1.0));
  const Eigen::MatrixXd A2 = Eigen::MatrixXd(implicit_matrix(l, {}, hinges, masses, slot, l.rest, 2.0));
  const Eigen::MatrixXd K = (A2 - 2 * A1 + M) / 2, C = A1 - M - K;
  const Eigen::Matrix3Xd v0 = Eigen::Matrix3Xd::Zero(3, 4);
  auto force = [&](const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 4);
    add_forces(l, {}, hinges, {}, {}, x, v, f);
    return Eigen::Map<const Eigen::VectorXd>(f.data(), 12).eval();
  };
  const double eps = 1e-7;
  for (int col = 0; col < 12; ++col) {
    Eigen::Matrix3Xd xp = l.rest, xm = l.rest, vp = v0, vm = v0;
    xp.data()[col] += eps, xm.data()[col] -= eps, vp.data()[col] += eps, vm.data()[col] -= eps;
    EXPECT_LT((K.col(col) + (force(xp, v0) - force(xm, v0)) / (2 * eps)).norm(), 1e-6) << "column " << col;
    EXPECT_LT((C.col(col) + (force(l.rest, vp) - force(l.rest, vm)) / (2 * eps)).norm(), 1e-6) << "column " << col;
  }
  // K v agrees with the matrix.
  Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Random(3, 4), kv = Eigen::Matrix3Xd::Zero(3, 4);
  add_stiffness_times(l, {}, hinges, l.rest, v, 1.0, kv);
  EXPECT_LT(
      (Eigen::Map<const Eigen::VectorXd>(kv.data(), 12) - K * Eigen::Map<const Eigen::VectorXd>(v.data(), 12)).norm(),
      1e-9);
}

TEST(MassspringHinge, SheetAndDomeMeshesGetOneHingePerInteriorEdge) {
  // A 3 x 3 grid of squares, two triangles each: 9 diagonals and 12
  // interior grid edges.
  Lattice sheet = make_sheet(4, 4, 0.01, {});
  std::vector<Eigen::Vector3i> tris;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = i + 4 * j;
      tris.emplace_back(a, a + 1, a + 5);
      tris.emplace_back(a, a + 5, a + 4);
    }
  add_hinges(sheet, tris, 1e-4, 0);
  EXPECT_EQ(sheet.quartets.size(), 21u);
  for (const Quartet& h : sheet.quartets) {
    EXPECT_NEAR(h.rest, 0, 1e-15);
    EXPECT_GT(h.stiffness, 0);
  }
  EXPECT_NO_THROW(check(sheet));
  // A closed octahedron: 12 edges, each convex by the same angle.
  Lattice oct;
  oct.rest.resize(3, 6);
  oct.rest << 1, -1, 0, 0, 0, 0, 0, 0, 1, -1, 0, 0, 0, 0, 0, 0, 1, -1;
  oct.mass.setConstant(6, 1), oct.anchored.assign(6, 0);
  const std::vector<Eigen::Vector3i> faces{{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                           {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  add_hinges(oct, faces, 1, 0);
  ASSERT_EQ(oct.quartets.size(), 12u);
  // Normals of neighbouring faces 70.5 degrees apart (interior angle 109.5).
  for (const Quartet& h : oct.quartets) EXPECT_NEAR(std::abs(h.rest), std::acos(1.0 / 3), 1e-12);
  const double first = oct.quartets[0].rest;
  for (const Quartet& h : oct.quartets) EXPECT_NEAR(h.rest, first, 1e-12);
}

TEST(MassspringHinge, BadMeshesAndHingesAreNamed) {
  Lattice l = make_sheet(3, 3, 0.01, {});
  EXPECT_NE(tests::message_of([&] { add_hinges(l, {{0, 1, 9}}, 1, 0); }).find("triangle 0"), std::string::npos);
  EXPECT_NE(tests::message_of([&] { add_hinges(l, {{0, 1, 2}}, 1, 0); }).find("no area"), std::string::npos);
  EXPECT_NE(tests::message_of([&] {
              add_hinges(l, {{0, 1, 4}, {0, 1, 3}}, 1, 0);
            }).find("same way"),
            std::string::npos);
  EXPECT_NE(tests::message_of([&] { add_hinges(l, {{0, 1, 4}}, -1, 0); }).find("rigidity"), std::string::npos);
  l.quartets.push_back({0, 1, 4, 1, 0, 1, 0});
  EXPECT_NE(tests::message_of([&] { check(l); }).find("hinge 0"), std::string::npos);
  l.quartets[0] = {0, 1, 4, 3, 4.0, 1, 0};
  EXPECT_NE(tests::message_of([&] { check(l); }).find("rest angle"), std::string::npos);
}

// A tetrahedron with its corners at (0,0,0), (1,0,0), (0,1,0) and (0,0,1),
// scaled by `scale` along z (negative: mirrored).
Lattice tetrahedron(double scale = 1) {
  Lattice l;
  l.rest.resize(3, 4);
  l.rest << 0, 1, 0, 0.1, 0, 0, 1, 0.2, 0, 0, 0, scale;
  l.mass.setConstant(4, 1e-3);
  l.anchored.assign(4, 0);
  return l;
}

TEST(MassspringVolume, GradientIsTheVolumeFiniteDifferenceAndTheSignTellsAnInvertedElement) {
  const Quartet t{0, 1, 2, 3, 0, 1, 0, Measure::volume};
  Eigen::Vector3d g[4], unused[4];
  EXPECT_NEAR(volume(t, tetrahedron().rest, g), 1.0 / 6, 1e-15);
  EXPECT_NEAR(volume(t, tetrahedron(-1).rest, g), -1.0 / 6, 1e-15);
  for (const double scale : {2.0, 0.01, -0.7}) {
    const Eigen::Matrix3Xd x = tetrahedron(scale).rest;
    volume(t, x, g);
    EXPECT_LT((g[0] + g[1] + g[2] + g[3]).norm(), 1e-15);  // a translation keeps the volume
    const double eps = 1e-7;
    for (int c = 0; c < 4; ++c)
      for (int a = 0; a < 3; ++a) {
        Eigen::Matrix3Xd xp = x, xm = x;
        xp(a, c) += eps, xm(a, c) -= eps;
        EXPECT_NEAR(g[c][a], (volume(t, xp, unused) - volume(t, xm, unused)) / (2 * eps), 1e-9);
      }
  }
}

TEST(MassspringVolume, AFloorActsBelowItsRestOnlyAndPushesTheElementBackOut) {
  Lattice l = tetrahedron();
  add_volumes(l, {{0, 1, 3, 2}}, 1000, 0.5, 0.5);  // given inside out: turned
  ASSERT_EQ(l.quartets.size(), 1u);
  const Quartet& t = l.quartets[0];
  EXPECT_EQ(t.measure, Measure::volume);
  EXPECT_NEAR(t.rest, 0.5 / 6, 1e-15);
  EXPECT_NEAR(t.stiffness, 1000 * 6, 1e-9);
  EXPECT_NEAR(t.b, 0.5 * 6, 1e-12);
  EXPECT_NO_THROW(check(l));
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, 4);
  Eigen::Vector3d f[4], g[4];
  // Above the floor, at rest and stretched: nothing.
  for (const double scale : {1.0, 0.6, 3.0}) {
    EXPECT_EQ(quartet_forces(t, tetrahedron(scale).rest, v, f), 0) << scale;
    for (int c = 0; c < 4; ++c) EXPECT_EQ(f[c].norm(), 0);
    EXPECT_EQ(quartet_energy(t, tetrahedron(scale).rest), 0);
  }
  // Flattened and inverted: a force along the volume's gradient, none net,
  // no moment, minus the energy's gradient.
  for (const double scale : {0.3, 0.0, -1.0}) {
    const Eigen::Matrix3Xd x = tetrahedron(scale).rest;
    const double d = quartet_forces(t, x, v, f);
    EXPECT_LT(d, 0) << scale;
    volume(t, x, g);
    double along = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
    for (int c = 0; c < 4; ++c) along += f[c].dot(g[c]), sum += f[c], moment += x.col(c).cross(f[c]);
    EXPECT_GT(along, 0) << scale;  // the volume grows under it
    EXPECT_LT(sum.norm(), 1e-12);
    EXPECT_LT(moment.norm(), 1e-12);
    const double eps = 1e-7;
    for (int c = 0; c < 4; ++c)
      for (int a = 0; a < 3; ++a) {
        Eigen::Matrix3Xd xp = x, xm = x;
        xp(a, c) += eps, xm(a, c) -= eps;
        EXPECT_NEAR(f[c][a], -(quartet_energy(t, xp) - quartet_energy(t, xm)) / (2 * eps), 1e-6);
      }
  }
}

TEST(MassspringVolume, FiveTetrahedraFillEachCellAlongTheSpringsDiagonals) {
  const int nx = 3, ny = 4, nz = 5;
  const double a = 0.01;
  Lattice l = make_box(nx, ny, nz, a, {}, Shear::one);
  const auto tets = box_tetrahedra(nx, ny, nz);
  ASSERT_EQ(tets.size(), 5u * (nx - 1) * (ny - 1) * (nz - 1));
  add_volumes(l, tets, 1, 0, 1);
  double total = 0;
  for (const Quartet& t : l.quartets) total += t.rest;
  EXPECT_NEAR(total, (nx - 1) * (ny - 1) * (nz - 1) * a * a * a, 1e-15);
  // Every edge of every tetrahedron is a spring: the face diagonals agree.
  std::set<std::pair<int, int>> springs;
  for (const Spring& s : l.springs) springs.emplace(std::min(s.i, s.j), std::max(s.i, s.j));
  for (const auto& t : tets)
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < p; ++q)
        EXPECT_TRUE(springs.count({std::min(t[p], t[q]), std::max(t[p], t[q])})) << t[p] << "-" << t[q];
}

TEST(MassspringVolume, BadTetrahedraAreNamed) {
  Lattice l = tetrahedron();
  EXPECT_NE(tests::message_of([&] {
              add_volumes(l, {{0, 1, 2, 4}}, 1, 0, 0.5);
            }).find("tetrahedron 0"),
            std::string::npos);
  EXPECT_NE(tests::message_of([&] { add_volumes(l, {{0, 1, 2, 3}}, -1, 0, 0.5); }).find("modulus"), std::string::npos);
  EXPECT_NE(tests::message_of([&] { add_volumes(l, {{0, 1, 2, 3}}, 1, 0, 1.5); }).find("floor"), std::string::npos);
  Lattice flat = tetrahedron(0);
  EXPECT_NE(tests::message_of([&] {
              add_volumes(flat, {{0, 1, 2, 3}}, 1, 0, 0.5);
            }).find("no volume"),
            std::string::npos);
  EXPECT_TRUE(l.quartets.empty());
  l.quartets.push_back({0, 1, 2, 3, -1, 1, 0, Measure::volume});
  EXPECT_NE(tests::message_of([&] { check(l); }).find("volume 0"), std::string::npos);
  EXPECT_NE(tests::message_of([&] { check(l); }).find("rest volume"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::models::massspring
