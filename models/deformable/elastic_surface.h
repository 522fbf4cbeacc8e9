// Seed 000's elastic objects (000 §2.2, Fig 7): a plane sheet held in a
// frame and a semi-sphere on its base ring, mass-spring surfaces with
// bending hinges (shape memory), touched through a proxy on their faces
// (models/deformable/proxy.h) coupled to the haptic point by a
// spring-damper; the surface takes the opposite of the force felt. No
// S-Chain: the behavior model runs at the servo rate.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "models/deformable/limits.h"
#include "models/deformable/object.h"
#include "models/deformable/proxy.h"
#include "models/haptic/friction.h"
#include "models/massspring/simulator.h"

namespace hcosim::models::deformable {

enum class Shape { sheet, semisphere };
const char* name(Shape shape);

struct SurfaceSpec {
  Shape shape = Shape::sheet;
  int resolution = 21;  // sheet: masses per edge; semi-sphere: latitude rings (4 x as many masses at its base)
  double size = 0.1;    // m: sheet edge, or semi-sphere radius
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // m, world: sheet centre, or semi-sphere base centre
  models::massspring::Material material{1e-3, 20, 0.02, 0.01};
  // Sheet: its springs' rest lengths are (1 - prestretch) times their
  // length in the frame, so it is taut. A slack membrane has no linear
  // stiffness out of its plane: pressed, it creeps back over seconds.
  double prestretch = 0.05;
  // J, >= 0: the surface's flexural rigidity D, as hinges across its edges
  // (models/massspring/quartet.h), damped in proportion (material b / k).
  // A membrane of springs alone has no rest shape out of its plane: a dome
  // pressed inside out stays so, since inverting it stretches no spring.
  // 2e-6 J (a rubber skin about 0.3 mm thick) brings the default scene's
  // dome and sheet back within 0.1 mm of rest within a second of release
  // while adding at most one substep at the servo rate; the explicit
  // integrators' stable step falls as 1 / sqrt(D) once bending dominates.
  double bending = 2e-6;
  // m, >= 0: the stylus tip's; the surface is touched by the tip's sphere:
  // the HIP meets the surface grown by this along its vertex normals.
  double tip_radius = 0;
  haptic::Friction friction;  // the stylus on the surface
  // N/m, > 0: the coupling between proxy and haptic point (Colgate et al.
  // 1995), in series with the surface. 5 times the springs' k (the
  // deformable service's default): the default sheet pressed 4 mm then
  // pushes back 0.88 of what it would through a 50 times stiffer one, the
  // dome 0.99, while one encoder count of the Omni (0.055 mm) changes the
  // force by 5.5 mN. At 2,000 N/m a count changed it by more than a held
  // press's whole force, a kick that threw the surface off the stylus.
  double contact_stiffness = 100;
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

  // The HIP touches where its path from the last tick crosses the current
  // (grown) surface from outside (sheet: from +z; semi-sphere: from
  // outside the dome), and stays in contact while the coupling pushes it
  // out (or, with `grab`, until grab ends: then it pulls too, and sticks).
  // The coupling is solved in each behavior substep with the touched
  // point's inertia, so that a light membrane neither runs ahead of the
  // HIP nor chatters. dt must equal options.dt.
  Touch touch(double dt, const Eigen::Vector3d& hip, bool grab) override;
  // Where a contact can begin: the sheet's frame from half its edge below
  // to a tenth above (a membrane released swings a little past its
  // plane), or the dome's half ball grown by a twentieth; each grown by
  // the tip's radius.
  Eigen::AlignedBox3d reach() const override;
  double behavior_dt() const override { return 0; }
  void couple() override {}
  void integrate() override {}
  Eigen::Matrix3Xd cage() const override { return state_.x; }
  Eigen::Matrix3Xd surface_from(const Eigen::Matrix3Xd& cage) const override { return cage; }
  const std::vector<Eigen::Vector3i>& triangles() const override { return triangles_; }

  // The behavior model, stepping one substep of the servo period
  // (substeps() of them per touch()).
  const models::massspring::Simulator& behavior() const { return *sim_; }
  int substeps() const { return substeps_; }
  const models::massspring::State& state() const { return state_; }
  // The proxy's material point (face -1: no contact), its position on the
  // grown surface, and the loads the last touch() put on the surface (N,
  // by vertex, averaged over the tick's substeps, a vertex once per
  // substep; the frame's and base ring's included): their sum is minus the
  // force felt.
  const SurfacePoint& contact() const { return contact_; }
  Eigen::Vector3d proxy() const;
  // Untouched, and put back at rest exactly once every mass was within a
  // nanometre and a micrometre a second of it: touch() then steps nothing.
  bool resting() const { return resting_; }
  const std::vector<models::massspring::PointForce>& loads() const { return loads_; }

 private:
  // The surface the tip's centre touches: the masses' positions grown by
  // the tip's radius.
  Eigen::Matrix3Xd touched(const Eigen::Matrix3Xd& x) const;
  // The same of the current state, without a copy when the tip is a point
  // (in now_ otherwise): what the servo loop reads every substep.
  const Eigen::Matrix3Xd& touched_now();
  // One substep of h seconds' coupling force for the HIP at `hip` moving
  // at `hip_speed`: ends, holds or slides the contact, and appends the
  // load it puts on the touched face's vertices.
  Eigen::Vector3d couple(double h, const Eigen::Vector3d& hip, const Eigen::Vector3d& hip_speed, bool grab,
                         Eigen::Vector3d* normal, std::vector<models::massspring::PointForce>& loads);

  SurfaceSpec spec_;
  std::unique_ptr<models::massspring::Simulator> sim_;
  int substeps_ = 1;
  models::massspring::State state_;
  std::vector<Eigen::Vector3i> triangles_;
  std::unique_ptr<MeshProxy> mesh_;
  Eigen::Matrix3Xd rest_;  // the touched surface at rest
  haptic::FrictionCone cone_;
  SurfacePoint contact_;
  Eigen::Vector3d last_hip_ = Eigen::Vector3d::Zero();      // the previous tick's, for entry
  Eigen::Matrix3Xd last_x_;                                 // the touched surface then
  Eigen::Matrix3Xd now_;                                    // the touched surface now, with a tip radius
  std::vector<models::massspring::PointForce> step_loads_;  // one substep's, kept for its storage
  // At rest and untouched: touch() steps nothing (an untouched membrane
  // would otherwise cost its whole behavior step every servo tick).
  bool resting_ = true;
  bool has_last_ = false;
  std::vector<models::massspring::PointForce> loads_;
};

}  // namespace hcosim::models::deformable
