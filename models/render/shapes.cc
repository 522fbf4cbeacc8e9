#include "models/render/shapes.h"

#include <cmath>
#include <stdexcept>

namespace hcosim::models::render {
namespace {

void quad(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
}

}  // namespace

Mesh cube(double half) {
  if (!(half > 0)) throw std::invalid_argument("cube: half-edge must be > 0");
  Mesh m;
  m.vertices.resize(3, 24);
  int v = 0;
  // Each face: its normal axis and sign, corners counter-clockwise seen from outside.
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (int c = 0; c < 4; ++c) {
        Eigen::Vector3d p;
        p[axis] = sign * half;
        p[u] = corners[c][0] * half;
        p[w] = corners[c][1] * half * sign;
        m.vertices.col(v + c) = p;
      }
      quad(m, std::uint32_t(v), std::uint32_t(v + 1), std::uint32_t(v + 2), std::uint32_t(v + 3));
      v += 4;
    }
  return m;
}

Mesh sphere(double radius, int rings) {
  if (!(radius > 0) || rings < 3) throw std::invalid_argument("sphere: radius must be > 0 and rings >= 3");
  const int segments = 2 * rings;
  const double pi = std::acos(-1.0);
  Mesh m;
  m.vertices.resize(3, (rings + 1) * segments);
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double polar = pi * i / rings, azimuth = 2 * pi * j / segments;
      m.vertices.col(i * segments + j) = radius * Eigen::Vector3d(std::sin(polar) * std::cos(azimuth),
                                                                  std::sin(polar) * std::sin(azimuth), std::cos(polar));
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const auto at = [&](int r, int s) { return std::uint32_t(r * segments + (s % segments)); };
      quad(m, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

Mesh cylinder(double radius, double length, int sides) {
  if (!(radius > 0 && length > 0) || sides < 3)
    throw std::invalid_argument("cylinder: radius and length must be > 0 and sides >= 3");
  const double pi = std::acos(-1.0);
  Mesh m;
  m.vertices.resize(3, 2 * sides + 2);
  for (int j = 0; j < sides; ++j) {
    const double a = 2 * pi * j / sides;
    m.vertices.col(j) = Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), 0);
    m.vertices.col(sides + j) = Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), length);
  }
  const auto bottom = std::uint32_t(2 * sides), top = std::uint32_t(2 * sides + 1);
  m.vertices.col(bottom) = Eigen::Vector3d::Zero();
  m.vertices.col(top) = Eigen::Vector3d(0, 0, length);
  for (int j = 0; j < sides; ++j) {
    const auto a = std::uint32_t(j), b = std::uint32_t((j + 1) % sides);
    quad(m, a, b, b + std::uint32_t(sides), a + std::uint32_t(sides));
    m.triangles.insert(m.triangles.end(), {bottom, b, a, top, a + std::uint32_t(sides), b + std::uint32_t(sides)});
  }
  return m;
}

Mesh placed(const Mesh& m, const Eigen::Isometry3d& pose) { return {pose * m.vertices, m.triangles}; }

}  // namespace hcosim::models::render
