// What the AR view draws over a camera frame: the scene's objects as
// triangle meshes (world frame, the marker's), the stylus, and the force
// it renders as an arrow from its tip.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "models/render/canvas.h"
#include "models/render/shapes.h"

namespace hcosim::models::render {

struct Object {
  std::string name;
  Mesh mesh;          // world frame, m
  cv::Scalar colour;  // BGR
};

struct Stylus {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();              // haptic interface point, world, m
  Eigen::Matrix3d orientation = Eigen::Matrix3d::Identity();  // stylus to world; the pen runs along +z from the tip
  Eigen::Vector3d force = Eigen::Vector3d::Zero();            // N, on the stylus, world
};

struct View {
  std::vector<Object> objects;
  std::optional<Stylus> stylus;
  double force_scale = 0.02;     // m of arrow per N
  double stylus_length = 0.08;   // m
  double stylus_radius = 0.003;  // m
};

// The colour of the i-th object: distinct, and apart from the marker's
// black, white and grey.
cv::Scalar object_colour(std::size_t i);

// Draws `v` onto `c`: objects and stylus with the depth test, then the
// force arrow over everything (a force is read, not hidden). Forces under
// 0.01 N draw no arrow.
void draw(const View& v, Canvas& c);

}  // namespace hcosim::models::render
