// Building the hybrid model: the seed's meshes, the lattices on one grid
// of nodes with the stiff side stiffer, the visual map's cage, the gain
// points, and shapes refused by name.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "models/deformable/hybrid_build.h"
#include "models/deformable/surface.h"
#include "tests/support/shapes.h"
#include "tests/support/temp_dir.h"

namespace hcosim::models::deformable {
namespace {

TEST(HybridSurfaces, SeedMeshesAreClosedAndFaceOutward) {
  const models::massspring::TriangleMesh v = rounded_box(30, -Eigen::Vector3d::Ones(), Eigen::Vector3d::Ones(), 8);
  EXPECT_EQ(v.vertices.cols(), 5402);  // 001 Fig 7
  EXPECT_EQ(v.triangles.size(), 10800u);
  models::massspring::check_closed(v);
  EXPECT_GT(tests::signed_volume(v.vertices, v.triangles), 0);
  EXPECT_NEAR(height_over(v.vertices, v.triangles, {0, 0}), 1, 1e-12);  // the top face's centre
  EXPECT_EQ(height_over(v.vertices, v.triangles, {2, 0}), -std::numeric_limits<double>::infinity());
  const Eigen::Matrix3Xd n = vertex_normals(v.vertices, v.triangles);
  for (int i = 0; i < n.cols(); ++i) ASSERT_GT(n.col(i).dot(v.vertices.col(i)), 0) << "vertex " << i;

  const GridSurface g = grid_surface(10, 10, 10);
  EXPECT_EQ(g.nodes.size(), 488u);  // 1000 - 8^3
  EXPECT_EQ(g.triangles.size(), 972u);
  models::massspring::TriangleMesh cage{Eigen::Matrix3Xd(3, g.nodes.size()), g.triangles};
  for (std::size_t i = 0; i < g.nodes.size(); ++i)
    cage.vertices.col(i) << g.nodes[i] % 10, (g.nodes[i] / 10) % 10, g.nodes[i] / 100;
  models::massspring::check_closed(cage);
  EXPECT_NEAR(tests::signed_volume(cage.vertices, cage.triangles), 729, 1e-9);
}

// The seed's cube (001 Fig 7): 10^3 chain elements and masses on one grid,
// its bottom layer anchored in both, the spec's box at rest; with a
// stiff_ratio the +x half's springs, volume floors, chains and FEM
// tetrahedra are that much stiffer and its chains' ranges that much
// shorter, and the -x half's are not.
TEST(HybridBuild, TheCubesLatticesShareOneGridAndTheStiffSideIsStiffer) {
  HybridSpec s;
  s.stiff_ratio = 4;
  const models::massspring::Lattice masses = hybrid_masses(s);
  const ChainLattice chains = hybrid_chains(s);
  const models::fem::Mesh mesh = hybrid_mesh(s);
  ASSERT_EQ(masses.size(), 1000);
  ASSERT_EQ(chains.size(), 1000);
  ASSERT_EQ(mesh.size(), 1000);
  const Eigen::AlignedBox3d box = rest_box(s);
  EXPECT_LT((box.min() - (s.centre - Eigen::Vector3d::Constant(0.05))).norm(), 1e-12);
  int anchored = 0;
  for (int e = 0; e < 1000; ++e) {
    EXPECT_LT((chains.rest(e) - masses.rest.col(e)).norm(), 1e-12) << e;
    EXPECT_LT((mesh.rest.col(e) - masses.rest.col(e)).norm(), 1e-12) << e;
    const bool bottom = masses.rest(2, e) < box.min().z() + 1e-9;
    EXPECT_EQ(bool(masses.anchored[e]), bottom) << e;
    EXPECT_EQ(bool(chains.anchored[e]), bottom) << e;
    EXPECT_EQ(bool(mesh.anchored[e]), bottom) << e;
    anchored += bottom;
    const bool stiff = masses.rest(0, e) > s.centre.x() + 1e-9;
    EXPECT_EQ(chains.material[e].stiffness, s.chain.stiffness * (stiff ? 4 : 1)) << e;
    EXPECT_EQ(chains.material[e].stretch, s.chain.stretch / (stiff ? 4 : 1)) << e;
  }
  EXPECT_EQ(anchored, 100);
  for (const models::massspring::Spring& sp : masses.springs) {
    const bool stiff = masses.rest(0, sp.i) > s.centre.x() + 1e-9 && masses.rest(0, sp.j) > s.centre.x() + 1e-9;
    ASSERT_EQ(sp.k, s.material.k * (stiff ? 4 : 1));
  }
  int stiff_tets = 0;
  for (const double f : mesh.scale) stiff_tets += f == 4;
  EXPECT_EQ(stiff_tets, 5 * 4 * 9 * 9);  // five to each cell of the four +x columns of cells
  EXPECT_EQ(mesh.tets.size(), 5u * 9 * 9 * 9);
}

// The map's cage is the lattice's boundary, closed around its cells; a
// shape's is drawn toward the shape's surface by under half a cell.
TEST(HybridBuild, TheMapsCageIsTheLatticesBoundary) {
  HybridSpec s;
  const models::massspring::Voxels voxels = hybrid_voxels(s);
  const models::massspring::Lattice lattice = hybrid_masses(s);
  const Cage cube = map_cage(s, voxels, lattice, hybrid_visual(s));
  EXPECT_EQ(cube.masses.size(), 488u);
  for (std::size_t v = 0; v < cube.masses.size(); ++v)
    ASSERT_LT((cube.rest.col(v) - lattice.rest.col(cube.masses[v])).norm(), 1e-15);
  models::massspring::check_closed({cube.rest, cube.triangles});
  EXPECT_NEAR(tests::signed_volume(cube.rest, cube.triangles), std::pow(s.size, 3), 1e-12);

  s.shape = tests::loaf(), s.size = 0.04, s.elements = 16;
  const models::massspring::Voxels shape_voxels = hybrid_voxels(s);
  const models::massspring::Lattice shape_lattice = hybrid_masses(s);
  const Cage shape = map_cage(s, shape_voxels, shape_lattice, hybrid_visual(s));
  double most = 0;
  for (std::size_t v = 0; v < shape.masses.size(); ++v)
    most = std::max(most, (shape.rest.col(v) - shape_lattice.rest.col(shape.masses[v])).norm());
  EXPECT_GT(most, 0);
  EXPECT_LE(most, 0.45 * shape_voxels.spacing * (1 + 1e-12));
  s.map = VisualMap::trilinear;
  s.shape = {};
  EXPECT_EQ(map_cage(s, voxels, lattice, hybrid_visual(s)).masses.size(), 1000u);
}

// Each side's gain point is on the top, half a cell off a node of the
// side's middle column: at x a quarter of the way in from the side's
// face, the whole top's middle without a stiff_ratio.
TEST(HybridBuild, TheGainPointsAreOnTheTopAtEachSidesMiddle) {
  HybridSpec s;
  const models::massspring::Voxels voxels = hybrid_voxels(s);
  const SChain chains(hybrid_chains(s), s.relax_rate, s.limit_stiffness);
  const double top = rest_box(s).max().z(), cell = s.size / (s.elements - 1);
  const auto [middle, element] = find_gain_point(s, voxels, chains, false);
  EXPECT_NEAR(middle.z(), top, 1e-12);
  EXPECT_NEAR(middle.x(), s.centre.x() + 0.5 * cell, 0.5 * cell + 1e-12);
  EXPECT_NEAR(middle.y(), s.centre.y() + 0.5 * cell, 0.5 * cell + 1e-12);
  EXPECT_LT((chains.lattice().rest(element) - middle).norm(), cell);
  s.stiff_ratio = 4;
  const SChain stiff_chains(hybrid_chains(s), s.relax_rate, s.limit_stiffness);
  const Eigen::Vector3d soft = find_gain_point(s, voxels, stiff_chains, false).first,
                        stiff = find_gain_point(s, voxels, stiff_chains, true).first;
  EXPECT_LT(soft.x(), s.centre.x() - 0.2 * s.size);
  EXPECT_GT(stiff.x(), s.centre.x() + 0.2 * s.size);
  EXPECT_NEAR(soft.z(), top, 1e-12);
  EXPECT_NEAR(stiff.z(), top, 1e-12);
}

TEST(HybridBuild, AShapeWithoutAFloorOrOpenIsRefusedByName) {
  HybridSpec s;
  s.shape = tests::loaf();
  s.size = 0.04;
  // An octahedron standing on a vertex: no cell of its lowest layer is inside.
  s.shape.vertices.resize(3, 6);
  s.shape.vertices << 1, -1, 0, 0, 0, 0, 0, 0, 1, -1, 0, 0, 0, 0, 0, 0, 1, -1;
  s.shape.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  s.elements = 7;
  EXPECT_NE(tests::message_of([&] { hybrid_masses(s); }).find("flat underside"), std::string::npos);
  s.shape = tests::loaf();
  s.shape.triangles.pop_back();
  EXPECT_NE(tests::message_of([&] { hybrid_visual(s); }).find("not closed"), std::string::npos);
  s.shape = tests::loaf();
  s.map = VisualMap::trilinear;
  EXPECT_NE(tests::message_of([&] { hybrid_voxels(s); }).find("mvc"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::models::deformable
