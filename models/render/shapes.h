// Triangle meshes of the shapes the AR view draws that no model meshes for
// it: rigid cubes and spheres, and the stylus. Each is in its own frame
// (centred at the origin; the cylinder along +z from the origin), to be
// placed by the caller.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hcosim::models::render {

struct Mesh {
  Eigen::Matrix3Xd vertices;             // m
  std::vector<std::uint32_t> triangles;  // 3 indices each, counter-clockwise seen from outside
};

// A cube of half-edge `half` (m): 24 vertices (flat faces), 12 triangles.
// Throws std::invalid_argument unless half > 0.
Mesh cube(double half);

// A sphere of `radius` (m): `rings` latitude bands of 2 rings segments.
// Throws std::invalid_argument unless radius > 0 and rings >= 3.
Mesh sphere(double radius, int rings = 12);

// A closed cylinder of `radius` from z = 0 to z = `length` (m), `sides`
// sides. Throws std::invalid_argument unless both are > 0 and sides >= 3.
Mesh cylinder(double radius, double length, int sides = 12);

// `m` moved by `pose`.
Mesh placed(const Mesh& m, const Eigen::Isometry3d& pose);

}  // namespace hcosim::models::render
