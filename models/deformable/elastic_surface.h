// Seed 000's elastic objects (000 §2.2, Fig 7): a plane sheet held in a
// frame and a semi-sphere on its base ring, mass-spring surfaces with
// bending hinges (shape memory), touched by the stylus at one vertex. The
// contacted vertex is held at the haptic point; the springs and hinges
// around it pass the deformation on, and their pull on it is the force on
// the stylus. No S-Chain: the behavior model runs at the servo rate.
#pragma once

#include <memory>
#include <string>

#include "models/deformable/object.h"
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
  // m, >= 0: the stylus tip's; the surface is touched by the tip's sphere,
  // at the HIP less this along the surface's outward normal.
  double tip_radius = 0;
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

  // The HIP touches when it crosses the rest surface from outside (sheet:
  // from +z, within the frame; semi-sphere: into the dome); the free vertex
  // nearest the crossing is held at the HIP until it is back outside that
  // vertex's rest tangent plane (or, with `grab`, until grab ends). Then
  // one behavior step. dt must equal options.dt.
  Touch touch(double dt, const Eigen::Vector3d& hip, bool grab) override;
  // Where inside() can hold: under the sheet's frame down to half its
  // edge, or the dome's half ball.
  Eigen::AlignedBox3d reach() const override;
  double behavior_dt() const override { return 0; }
  void couple() override {}
  void integrate() override {}
  Eigen::Matrix3Xd cage() const override { return state_.x; }
  Eigen::Matrix3Xd surface_from(const Eigen::Matrix3Xd& cage) const override { return cage; }
  const std::vector<Eigen::Vector3i>& triangles() const override { return triangles_; }

  const models::massspring::Simulator& behavior() const { return *sim_; }
  const models::massspring::State& state() const { return state_; }
  int contact() const { return contact_; }

 private:
  bool inside(const Eigen::Vector3d& hip) const;
  Eigen::Vector3d rest_normal(int vertex) const;

  SurfaceSpec spec_;
  std::unique_ptr<models::massspring::Simulator> sim_;
  models::massspring::State state_;
  std::vector<Eigen::Vector3i> triangles_;
  int contact_ = -1;
};

}  // namespace hcosim::models::deformable
