// The god-object of haptic rendering (Zilles and Salisbury 1995; Ruspini
// et al. 1997) on a triangle mesh: the proxy is a material point of the
// mesh, a face and barycentric coordinates on it, so that it rides on the
// surface as the surface deforms. It is placed where the device point's
// path (HIP) first crossed the surface from outside, and moves over the
// faces only when friction lets it (models/haptic/friction.h). The stylus
// is a point: its tip has no radius here.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hcosim::models::deformable {

// A point on a face: its vertices' weights, >= 0, summing to 1.
struct SurfacePoint {
  int face = -1;  // -1: none
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
};

class MeshProxy {
 public:
  // `triangles` index `vertices` positions, counter-clockwise seen from
  // outside. Throws std::invalid_argument for an index outside them or no
  // triangle.
  MeshProxy(std::vector<Eigen::Vector3i> triangles, int vertices);

  // Where the HIP's path from `from` over the surface at positions x
  // (3 x vertices, world, m) to `to` under it went in: the crossing
  // nearest `from` among `faces` (every face when null); face -1 if it did
  // not go in.
  SurfacePoint entry(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                     const std::vector<int>* faces = nullptr) const;

  // The point of the mesh nearest q, among all faces: where a HIP with no
  // path from outside (the first one seen) is put.
  SurfacePoint closest(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& q) const;
  // Whether q is behind the mesh at p (its point nearest q): inside, for
  // a closed mesh.
  bool behind(const Eigen::Matrix3Xd& x, const SurfacePoint& p, const Eigen::Vector3d& q) const {
    return (q - point(x, p)).dot(normal(x, p)) < 0;
  }

  // The point of the mesh nearest q, found by walking from `start` over
  // the faces sharing a vertex with the current one: the proxy's new
  // material point after a slide of a few faces at most.
  SurfacePoint nearest(const Eigen::Matrix3Xd& x, SurfacePoint start, const Eigen::Vector3d& q) const;

  // A face's outward unit normal (+z for a collapsed face), and the
  // surface's smooth one at p: its vertices' area-weighted normals blended
  // by p's weights. A proxy pushed along its face's normal flips between
  // the two faces of a crease and shakes a membrane; along the smooth one
  // it is pushed the same way from either side.
  Eigen::Vector3d normal(const Eigen::Matrix3Xd& x, int face) const;
  Eigen::Vector3d normal(const Eigen::Matrix3Xd& x, const SurfacePoint& p) const;
  // Where p is at positions x.
  Eigen::Vector3d point(const Eigen::Matrix3Xd& x, const SurfacePoint& p) const;

  const Eigen::Vector3i& triangle(int face) const { return triangles_[face]; }
  int faces() const { return int(triangles_.size()); }

  // The surface grown by r (m, >= 0): each vertex moved out along its
  // area-weighted normal, the surface a tip of radius r's centre touches.
  Eigen::Matrix3Xd grown(const Eigen::Matrix3Xd& x, double r) const;

 private:
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<std::vector<int>> ring_;      // per face: the faces sharing a vertex with it, itself included
  std::vector<std::vector<int>> incident_;  // per vertex: its faces
};

// The point of triangle (a, b, c) nearest p, as barycentric weights.
Eigen::Vector3d nearest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c);

// Faces binned on a uniform grid by their boxes at positions x, for
// entry() on a mesh that does not move (the hybrid model's rest surface).
class FaceGrid {
 public:
  // cell: m, > 0; a face's box is grown by `margin` (m, >= 0) before binning.
  FaceGrid(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles, double cell, double margin);
  // Into `out` (its storage reused, for a 1 kHz loop): the faces whose
  // grown boxes may meet `box`, each once.
  void near(const Eigen::AlignedBox3d& box, std::vector<int>& out) const;

 private:
  Eigen::Vector3d origin_;
  Eigen::Vector3i dims_;
  double cell_;
  std::vector<std::vector<int>> bins_;
};

}  // namespace hcosim::models::deformable
