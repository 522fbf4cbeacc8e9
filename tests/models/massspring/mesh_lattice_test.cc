// The OBJ reader and voxeliser: a cube, a sphere's volume, welded
// duplicates, and errors that name the file and line.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "models/massspring/mesh_lattice.h"
#include "tests/support/temp_dir.h"

namespace hcosim::models::massspring {
namespace {

class MeshFiles : public ::testing::Test {
 protected:
  tests::TempDir dir;
  std::string write(const std::string& name, const std::string& text) { return dir.file(name, text); }
};

// An axis-aligned cube [0, s]^3 as quads, with 'v//n' style indices.
std::string cube_obj(double s) {
  std::ostringstream o;
  for (int k = 0; k < 8; ++k) o << "v " << s * (k & 1) << " " << s * ((k >> 1) & 1) << " " << s * (k >> 2) << "\n";
  o << "# six faces, outward\nf 1//1 3//1 4//1 2//1\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  return o.str();
}

// A UV sphere of radius r: rings x segments, closed at both poles.
std::string sphere_obj(double r, int rings, int segs) {
  std::ostringstream o;
  o << "v 0 0 " << r << "\n";
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segs; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / segs;
      o << "v " << r * std::sin(th) * std::cos(ph) << " " << r * std::sin(th) * std::sin(ph) << " " << r * std::cos(th)
        << "\n";
    }
  o << "v 0 0 " << -r << "\n";
  const int south = 2 + (rings - 1) * segs;
  auto id = [segs](int i, int j) { return 2 + (i - 1) * segs + (j % segs); };
  for (int j = 0; j < segs; ++j) o << "f 1 " << id(1, j) << " " << id(1, j + 1) << "\n";
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segs; ++j)
      o << "f " << id(i, j) << " " << id(i + 1, j) << " " << id(i + 1, j + 1) << " " << id(i, j + 1) << "\n";
  for (int j = 0; j < segs; ++j) o << "f " << south << " " << id(rings - 1, j + 1) << " " << id(rings - 1, j) << "\n";
  return o.str();
}

TEST_F(MeshFiles, VoxelisedCubeIsTheBox) {
  const Lattice l = make_from_mesh(read_obj(write("cube.obj", cube_obj(0.1))), 0.01, {});
  const Lattice box = make_box(11, 11, 11, 0.01, {});
  EXPECT_EQ(l.size(), box.size());
  EXPECT_EQ(l.springs.size(), box.springs.size());
}

TEST_F(MeshFiles, VoxelisedSphereHasTheSphereVolume) {
  const double r = 0.05, h = 0.005;
  const Lattice l = make_from_mesh(read_obj(write("sphere.obj", sphere_obj(r, 24, 32))), h, {});
  // Masses sit on the corners of inside cells: about (2r/h + 1)^3 pi / 6.
  const double expect = M_PI / 6 * std::pow(2 * r / h + 1, 3);
  EXPECT_NEAR(l.size(), expect, 0.08 * expect);
  for (int i = 0; i < l.size(); ++i) EXPECT_LT(l.rest.col(i).norm(), r + 1.8 * h);
}

TEST(Voxels, AFullBoxIsMakeBoxSpringForSpring) {
  for (const Shear shear : {Shear::one, Shear::both}) {
    const Lattice v = make_from_voxels(box_voxels(3, 4, 5, 0.01), {}, shear);
    const Lattice box = make_box(4, 5, 6, 0.01, {}, shear);
    ASSERT_EQ(v.size(), box.size());
    EXPECT_EQ((v.rest - box.rest).norm(), 0);
    ASSERT_EQ(v.springs.size(), box.springs.size());
    for (std::size_t s = 0; s < box.springs.size(); ++s) {
      EXPECT_EQ(v.springs[s].i, box.springs[s].i);
      EXPECT_EQ(v.springs[s].j, box.springs[s].j);
    }
  }
}

TEST(Voxels, AnLShapeHasOnlyItsCellsSpringsAndTetrahedra) {
  // Two by two cells with one missing: an L of three cells in one layer.
  Voxels v = box_voxels(2, 2, 1, 0.01);
  v.filled[v.cell(1, 1, 0)] = 0;
  const std::vector<int> id = v.masses();
  EXPECT_EQ(id[v.node(2, 2, 0)], -1);
  EXPECT_EQ(id[v.node(2, 2, 1)], -1);
  const Lattice l = make_from_voxels(v, {});
  EXPECT_EQ(l.size(), 18 - 2);
  // Each of the 3 cells' 12 edges and 6 face diagonals, shared ones once:
  // edges 12 + 8 + 8 = 28 (the two joints share 4 edges each), diagonals
  // 6 * 3 - 2 shared faces = 16.
  EXPECT_EQ(l.springs.size(), 28u + 16u);
  double volume = 0;
  for (const auto& t : voxel_tetrahedra(v)) {
    const Eigen::Vector3d a = l.rest.col(t[0]);
    volume += std::abs((l.rest.col(t[1]) - a).dot((l.rest.col(t[2]) - a).cross(l.rest.col(t[3]) - a))) / 6;
  }
  EXPECT_NEAR(volume, 3e-6, 1e-15);
}

TEST_F(MeshFiles, DuplicateVerticesAreWelded) {
  // The cube with every face carrying its own copy of its corners.
  std::ostringstream o;
  const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (int f = 0; f < 6; ++f) {
    for (int c = 0; c < 4; ++c) {
      const int k = faces[f][c] - 1;
      o << "v " << 0.1 * (k & 1) << " " << 0.1 * ((k >> 1) & 1) << " " << 0.1 * (k >> 2) << "\n";
    }
    o << "f -4 -3 -2 -1\n";
  }
  TriangleMesh mesh = read_obj(write("soup.obj", o.str()));
  EXPECT_EQ(mesh.vertices.cols(), 24);
  EXPECT_EQ(weld(mesh, 1e-9), 16);
  EXPECT_EQ(make_from_mesh(read_obj(write("soup.obj", o.str())), 0.01, {}).size(), 1331);
}

TEST_F(MeshFiles, ErrorsNameTheFileAndLine) {
  EXPECT_NE(tests::message_of([&] {
              read_obj(write("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1\n"));
            }).find("a.obj:3: a vertex needs three numbers"),
            std::string::npos);
  EXPECT_NE(tests::message_of([&] {
              read_obj(write("b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"));
            }).find("b.obj:4: vertex index 7"),
            std::string::npos);
  EXPECT_NE(tests::message_of([&] { read_obj(write("c.obj", "v 0 0 0\nf 1 x 2\n")); }).find("c.obj:2: 'x'"),
            std::string::npos);
  EXPECT_NE(tests::message_of([&] { read_obj((dir.path / "missing.obj").string()); }).find("cannot open"),
            std::string::npos);
  // Found by fuzzing: a coordinate of 9e13 m made weld's grid cell overflow a long.
  EXPECT_NE(tests::message_of([&] {
              read_obj(write("far.obj", "v 0 0 0\nv 0 0 88888888888888\nv 0 1 0\nf 1 2 3\n"));
            }).find("far.obj:2: vertex coordinate beyond +-1e6 m"),
            std::string::npos);
  TriangleMesh far = read_obj(write("ok.obj", "v 0 0 0\nv 0 0 1e6\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_NE(tests::message_of([&] { weld(far, 1e-12); }).find("too large for a tolerance"), std::string::npos);
  EXPECT_NE(tests::message_of([&] { weld(far, 0); }).find("at least 1e-12"), std::string::npos);
  // An open box (top face missing) is refused before voxelising.
  std::string open = cube_obj(0.1);
  open = open.substr(0, open.rfind("f 2 4 8 6"));
  EXPECT_NE(tests::message_of([&] { make_from_mesh(read_obj(write("open.obj", open)), 0.01, {}); }).find("not closed"),
            std::string::npos);
  EXPECT_NE(
      tests::message_of([&] { make_from_mesh(read_obj(write("tiny.obj", cube_obj(0.1))), 0.5, {}); }).find("no cell"),
      std::string::npos);
}

}  // namespace
}  // namespace hcosim::models::massspring
