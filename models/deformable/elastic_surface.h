// Seed 000's elastic objects (000 §2.2, Fig 7): a plane sheet held in a
// frame and a semi-sphere on its base ring, pure mass-spring surfaces
// touched by the stylus. A proxy on the surface (models/deformable/proxy.h)
// is coupled to the haptic point by a stiff spring; the surface receives
// the opposite of the force felt, spread over the touched face's vertices
// by the proxy's barycentric weights, and friction lets the proxy slide
// over the faces. No S-Chain: the behavior model runs at the servo rate.
#pragma once

#include <memory>
#include <string>

#include "models/deformable/object.h"
#include "models/deformable/proxy.h"
#include "models/haptic/friction.h"
#include "models/massspring/simulator.h"

namespace hcosim::models::deformable {

enum class Shape { sheet, semisphere };
const char* name(Shape shape);

struct SurfaceSpec {
  Shape shape = Shape::sheet;
  int resolution = 21;  // sheet: masses per edge; semi-sphere: latitude rings (4 x as many segments)
  double size = 0.1;    // m: sheet edge, or semi-sphere radius
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // m, world: sheet centre, or semi-sphere base centre
  models::massspring::Material material{1e-3, 20, 0.02, 0.01};
  // Sheet: its springs' rest lengths are (1 - prestretch) times their
  // length in the frame, so it is taut. A slack membrane has no linear
  // stiffness out of its plane: pressed, it creeps back over seconds.
  double prestretch = 0.05;
  // Semi-sphere: bending springs across every inner edge
  // (massspring::add_bending), at this share of the material's k and b. A
  // membrane has next to no stiffness against a point pressed into it and
  // folds inward around it; these let a dome keep its shape under the
  // stylus, at the cost of the substeps their stiffness needs. 0: none.
  double bending = 0;
  haptic::Friction friction;        // the stylus on the surface
  double contact_stiffness = 5000;  // N/m, of the coupling between proxy and haptic point
  models::massspring::Options options = [] {
    models::massspring::Options o;
    o.integrator = models::massspring::Integrator::symplectic_euler;
    return o;
  }();  // options.dt is the servo period
};

class ElasticSurface final : public Object {
 public:
  // Throws std::invalid_argument for a bad spec.
  explicit ElasticSurface(const SurfaceSpec& spec);

  // The HIP touches where its path crosses the current surface from
  // outside (sheet: from +z; semi-sphere: from outside the dome), or, for
  // the first HIP seen, at the surface's nearest point if it is behind it;
  // and it stays
  // in contact while the coupling pushes it out (or, with `grab`, until
  // grab ends: then it pulls too, and sticks). The coupling is implicit in
  // the touched vertices' inertia, so that a light membrane neither runs
  // ahead of the HIP nor chatters. Then one behavior step under the
  // contact's load. dt must equal options.dt.
  Touch touch(double dt, const Eigen::Vector3d& hip, bool grab) override;
  // Where a contact can begin: the sheet's frame from half its edge below
  // to a twentieth above (a membrane released swings a little past its
  // plane), or the dome's half ball grown by a twentieth.
  Eigen::AlignedBox3d reach() const override;
  double behavior_dt() const override { return 0; }
  void couple() override {}
  void integrate() override {}
  Eigen::Matrix3Xd cage() const override { return state_.x; }
  Eigen::Matrix3Xd surface_from(const Eigen::Matrix3Xd& cage) const override { return cage; }
  const std::vector<Eigen::Vector3i>& triangles() const override { return triangles_; }

  const models::massspring::Simulator& behavior() const { return *sim_; }
  const models::massspring::State& state() const { return state_; }
  // The proxy's material point (face -1: no contact), its position on the
  // grown surface, and the loads the last touch() put on the surface (N,
  // by vertex, averaged over the tick's substeps, a vertex once per
  // substep; the frame's and base ring's included): their sum is minus the
  // force felt.
  const SurfacePoint& contact() const { return contact_; }
  Eigen::Vector3d proxy() const;
  const std::vector<models::massspring::PointForce>& loads() const { return loads_; }

 private:
  // One substep's coupling force for the HIP at `hip` moving at
  // `hip_speed`: ends, holds or slides the contact, and appends the load
  // it puts on the touched face's vertices.
  Eigen::Vector3d couple(double h, const Eigen::Vector3d& hip, const Eigen::Vector3d& hip_speed, bool grab,
                         Eigen::Vector3d* normal, std::vector<models::massspring::PointForce>& loads);

  SurfaceSpec spec_;
  std::unique_ptr<models::massspring::Simulator> sim_;
  int substeps_ = 1;  // behavior steps per servo tick
  models::massspring::State state_;
  std::vector<Eigen::Vector3i> triangles_;
  std::unique_ptr<MeshProxy> mesh_;
  haptic::FrictionCone cone_;
  SurfacePoint contact_;
  Eigen::Vector3d last_hip_ = Eigen::Vector3d::Zero();  // the previous tick's, for entry
  Eigen::Matrix3Xd last_x_;                             // the surface then
  bool has_last_ = false;
  std::vector<models::massspring::PointForce> loads_;
};

}  // namespace hcosim::models::deformable
