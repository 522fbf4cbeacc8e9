// Shapes the deformable models' tests build hybrid objects from, and a
// closed mesh's volume to check them by.
#pragma once

#include <algorithm>
#include <vector>

#include <Eigen/Geometry>

#include "models/deformable/surface.h"
#include "models/massspring/mesh_lattice.h"

namespace hcosim::tests {

// m^3: the volume a closed triangle mesh at positions x encloses, positive
// when its triangles face outward.
inline double signed_volume(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles) {
  double v = 0;
  for (const Eigen::Vector3i& f : triangles) v += x.col(f[0]).dot(x.col(f[1]).cross(x.col(f[2]))) / 6;
  return v;
}

// An organ from a mesh: a loaf, an ellipsoid of axes 2 : 1.2 : 1 cut flat
// at a fifth of its height, written in centimetres off the origin, to be
// scaled and put on the floor.
inline models::massspring::TriangleMesh loaf() {
  models::massspring::TriangleMesh m =
      models::deformable::rounded_box(16, Eigen::Vector3d(3, 4, 5), Eigen::Vector3d(7, 6.4, 7), 2);  // 4 x 2.4 x 2 cm
  for (int v = 0; v < m.vertices.cols(); ++v) m.vertices(2, v) = std::max(m.vertices(2, v), 5.4);
  return m;
}

}  // namespace hcosim::tests
