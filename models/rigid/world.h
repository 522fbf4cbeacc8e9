// The rigid scene of seed 000 §2.1: cubes and spheres that collide with
// one another and with the marker plane, with restitution and Coulomb
// friction, air friction and sleep, pushed by outside loads. Impulse-based:
// a contact changes velocities at once, conserving linear and angular
// momentum exactly.
//
// Two ways to touch a body. A load (set_load) is a wrench held over the
// steps: the haptic service's virtual coupling to the stylus
// (coupling.h), so that the body receives the force the hand feels. The
// tip is the seed's own model: a particle of its own mass with a radius
// for contact (the seed models stylus and object as particles), moving
// freely unless the caller sets it, its path swept each step against
// every body (continuous collision detection), so a 10 m/s stroke does not
// pass through a small object; eq 1-7 and the MuJoCo cross-check use it.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "models/rigid/body.h"

namespace hcosim::models::rigid {

// Restitution e in [0, 1] (1: elastic) and Coulomb friction mu >= 0.
struct Material {
  double restitution = 0.5;
  double friction = 0.3;
};

// Air friction, force -(linear + quadratic |v|) v and torque
// -(angular_linear + angular_quadratic |w|) w: the seed's "air friction"
// that makes motion stop. The defaults stop a 0.1 kg object within seconds,
// far sooner than real air would (its linear term is about 1e-5 N s/m).
struct Drag {
  double linear = 0.05;             // N s/m
  double quadratic = 0.001;         // N s^2/m^2
  double angular_linear = 1e-5;     // N m s
  double angular_quadratic = 1e-7;  // N m s^2
};

struct WorldSpec {
  Eigen::Vector3d gravity{0, 0, -9.81};  // m/s^2, world
  bool ground = true;                    // the marker plane z = 0, bodies above it
  Material tip;                          // tip against a body
  Material floor{0.2, 0.5};              // a body against the marker plane
  Material pair{0.5, 0.3};               // a body against another
  Drag drag;
  double tip_radius = 0.002;   // m, >= 0
  double tip_mass = 0.1;       // kg, > 0
  double bounce_speed = 0.05;  // m/s: slower impacts (floor or pair) do not bounce (resting contact)
  double sleep_speed = 2e-3;   // m/s: slower bodies (w times size counted as speed) may sleep
  double sleep_time = 0.3;     // s slower than sleep_speed before sleeping
};

// The stylus tip: a particle, world frame.
struct Tip {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // m
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // m/s
};

// What a step did.
struct StepReport {
  int hits = 0;       // tip-body impulses
  int touches = 0;    // body-body impulses
  int simulated = 0;  // bodies not asleep
};

// Throw std::invalid_argument naming the bad field (or body index).
void check(const WorldSpec& spec);
void check(const std::vector<Body>& bodies);

class World {
 public:
  // Throws std::invalid_argument for a bad spec or body (naming which).
  World(const WorldSpec& spec, std::vector<Body> bodies);

  // One step of dt (s, > 0): the tip's swept hits; gravity, loads and drag
  // for every body awake (a loaded body wakes and does not sleep); the
  // bodies' contacts with one another, then with the marker plane;
  // integration; then the tip moves.
  StepReport step(double dt);

  // The outside wrench on body i: force (N) through its centre and torque
  // about it (N m), world frame, held over every step until set again.
  // Throws std::invalid_argument for a bad index or a non-finite value.
  void set_load(std::size_t i, const Eigen::Vector3d& force, const Eigen::Vector3d& torque);

  // The tip, to drive it from a device (x, v finite; throws otherwise).
  void set_tip(const Tip& t);
  const Tip& tip() const { return tip_; }

  const std::vector<Body>& bodies() const { return bodies_; }

  // Totals over bodies and tip: momentum (kg m/s), angular momentum about
  // the world origin (kg m^2/s), kinetic energy (J).
  Eigen::Vector3d momentum() const;
  Eigen::Vector3d angular_momentum() const;
  double kinetic_energy() const;

 private:
  struct Load {
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  };
  void hit(Body& b, double dt, StepReport& r);
  bool touch(Body& a, Body& b, bool first, double dt, StepReport& r) const;
  void floor(Body& b, double dt) const;

  WorldSpec spec_;
  std::vector<Body> bodies_;
  std::vector<Load> loads_;
  Tip tip_;
};

// The impulse (N s) on a particle of mass `tip_mass` moving at tip_v that
// touches body b at world point p with unit normal n (out of the body):
// zero unless approaching. Without friction, Newton's restitution in
// closed form. With Coulomb friction, in closed form where p lies on the
// line through the centre along n (the slip keeps its direction);
// elsewhere integrated over the normal impulse in 400 increments (slip
// may stop or turn during the impact). Restitution is the ratio of
// restitution to compression impulse (Poisson). The body takes the
// opposite impulse at p.
Eigen::Vector3d contact_impulse(const Body& b, double tip_mass, const Eigen::Vector3d& tip_v, const Eigen::Vector3d& p,
                                const Eigen::Vector3d& n, const Material& m);

// The same law between two bodies touching at p with unit normal n (out of
// a, toward b): the impulse (N s) on b at p; a takes the opposite.
Eigen::Vector3d pair_impulse(const Body& a, const Body& b, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                             const Material& m);

// Earliest time in [0, dt] (s) at which the tip, moving at tip.v, touches
// body b moving at b.v (its rotation within the step neglected), or a
// negative number if it does not. Exact for a sphere; conservative
// advancement for a cube.
double time_of_impact(const Body& b, const Tip& tip, double tip_radius, double dt);

}  // namespace hcosim::models::rigid
