// CalculiX (`ccx`, Debian's calculix-ccx), the independent FEM reference
// that hcosim's deformable models are measured against: a static job on a
// mesh of hexahedra is written as CalculiX's input file, run, and its
// printed results read back. Units are SI (m, N, Pa).
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hcosim::adapters::reference {

// The material law: small-strain linear elasticity (`*ELASTIC`) or
// compressible neo-Hookean hyperelasticity (`*HYPERELASTIC, NEO HOOKE`,
// C10 = G / 2, D1 = 2 / K), with the same Young's modulus and Poisson's
// ratio.
enum class Law { linear, neo_hookean };

struct Material {
  double young = 10000;  // Pa, > 0
  double poisson = 0.3;  // [0, 0.5)
  Law law = Law::neo_hookean;
};

// A displacement held on every node of a set: `dof` 1, 2 or 3 (x, y, z).
struct Fix {
  std::string set;
  int dof = 1;
  double value = 0;  // m
};

// A force along `dof` (1, 2 or 3) whose total is `value` (N), its
// direction fixed (a dead load). The set's nodes share it equally, not as
// a consistent load of its faces: the resultant is right, its spread over
// the face is not, which matters only near that face.
struct Load {
  std::string set;
  int dof = 3;
  double value = 0;  // N
};

struct Job {
  std::string element = "C3D20";                 // C3D8 or C3D20 (quadratic)
  std::vector<Eigen::Vector3d> nodes;            // m
  std::vector<std::vector<int>> elements;        // node indices, in CalculiX's order for `element`
  std::map<std::string, std::vector<int>> sets;  // named node sets: upper case, A-Z 0-9 _
  Material material;
  bool nlgeom = true;  // large deformation
  std::vector<Fix> fixes;
  std::vector<Load> loads;
  std::vector<std::string> reactions;  // sets whose total reaction force is read back
};

struct Result {
  std::map<std::string, Eigen::Vector3d> reaction;  // N, total over each set of Job::reactions
  std::vector<Eigen::Vector3d> displacement;        // m, of every node
};

// A box [0, size] meshed with n[0] x n[1] x n[2] hexahedra of `element`,
// with node sets XMIN, XMAX, YMIN, YMAX, ZMIN and ZMAX of its faces.
// Throws std::invalid_argument for a size not > 0, fewer than one
// element along an axis, or another element type.
Job box(const Eigen::Vector3d& size, const std::array<int, 3>& n, const std::string& element = "C3D20");

// The job as CalculiX's input file. Throws std::invalid_argument for a
// material out of range, an element with the wrong node count or a node
// out of range, or a set that is empty or badly named.
std::string input_file(const Job& job);

// Whether `ccx` is on PATH.
bool ccx_available();

// Writes the job to `dir`/job.inp, runs ccx there and reads job.dat.
// Throws std::runtime_error, with the end of ccx's output, when ccx is
// missing, fails, or does not converge; std::invalid_argument for a bad
// job (input_file) or a folder whose name holds a quote.
Result run(const Job& job, const std::string& dir);

}  // namespace hcosim::adapters::reference
