#include "adapters/rigid/rigid_config.h"

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::adapters::rigid {
namespace {

using tests::message_of;

Config params(const std::string& text) { return Config::parse(text, "r.yaml", "params"); }

// The scene's marker is the plane the bodies stand on: its friction is
// the floor's unless the params give floor_friction.
TEST(RigidConfig, TheMarkersFrictionIsTheFloorsUnlessTheParamsSay) {
  MarkerSpec marker;
  marker.friction = 0.8;
  EXPECT_EQ(rigid_config(params("bodies: [{name: b}]\n"), marker).spec.floor.friction, 0.8);
  EXPECT_EQ(rigid_config(params("floor_friction: 0.1\nbodies: [{name: b}]\n"), marker).spec.floor.friction, 0.1);
  EXPECT_EQ(rigid_config(params("bodies: [{name: b}]\n"), {}).spec.floor.friction,
            models::rigid::WorldSpec().floor.friction);
}

TEST(RigidConfig, ReadsTheWorldAndItsBodies) {
  const RigidConfig r = rigid_config(params(
      "device: left\nbackend: crosscheck\nground: off\npair_friction: 0.7\nfloor_restitution: 0.1\ntip_radius: 0.003\n"
      "stiffness: 800\ndamping: 1.5\nmax_force: 2\nmujoco_substeps: 4\npair_restitution: 0.9\n"
      "bodies:\n  - {name: box, shape: cube, size: 0.02, mass: 0.05, centre: [0.01, 0, 0.02]}\n"
      "  - {name: ball, velocity: [0, 0, -1]}\n"));
  EXPECT_EQ(r.device, "left");
  EXPECT_EQ(r.backend, "crosscheck");
  EXPECT_FALSE(r.spec.ground);
  EXPECT_EQ(r.spec.pair.friction, 0.7);
  EXPECT_EQ(r.spec.pair.restitution, 0.9);
  EXPECT_EQ(r.spec.floor.restitution, 0.1);
  EXPECT_EQ(r.spec.floor.friction, models::rigid::WorldSpec().floor.friction);
  EXPECT_EQ(r.spec.tip_radius, 0.003);
  EXPECT_EQ(r.coupling.stiffness, 800);
  EXPECT_EQ(r.coupling.damping, 1.5);
  EXPECT_EQ(r.coupling.max_force, 2);
  EXPECT_EQ(r.mujoco_substeps, 4);
  ASSERT_EQ(r.names, (std::vector<std::string>{"box", "ball"}));
  EXPECT_EQ(r.bodies[0].shape, models::rigid::Shape::cube);
  EXPECT_EQ(r.bodies[0].mass, 0.05);
  EXPECT_EQ(r.bodies[0].x, Eigen::Vector3d(0.01, 0, 0.02));
  // A body's centre defaults to resting on the marker: its size above it.
  EXPECT_EQ(r.bodies[1].shape, models::rigid::Shape::sphere);
  EXPECT_EQ(r.bodies[1].x, Eigen::Vector3d(0, 0, r.bodies[1].size));
  EXPECT_EQ(r.bodies[1].v, Eigen::Vector3d(0, 0, -1));
}

TEST(RigidConfig, DefaultsAreTheDocumentedOnes) {
  const RigidConfig r = rigid_config(params("bodies: [{name: b}]\n"));
  EXPECT_EQ(r.device, "omni");
  EXPECT_EQ(r.backend, "analytic");
  EXPECT_TRUE(r.spec.ground);
  EXPECT_EQ(r.coupling.stiffness, 500);
  EXPECT_EQ(r.coupling.damping, 1);
  EXPECT_EQ(r.spec.tip_radius, 0);  // a point, unless the device or the params say
  EXPECT_EQ(r.coupling.max_force, 3.3);
  EXPECT_EQ(r.spec.pair.restitution, 0.5);
  EXPECT_EQ(r.spec.pair.friction, 0.3);
  EXPECT_EQ(r.mujoco_substeps, 10);
}

TEST(RigidConfig, EachBodysFrictionIsOneCoefficientOrStaticAndDynamic) {
  const RigidConfig r = rigid_config(params(
      "bodies:\n  - {name: a}\n  - {name: b, friction: 0}\n  - {name: c, friction: {static: 0.6, dynamic: 0.4}}\n"
      "  - {name: d, friction: 0.5}\n"));
  ASSERT_EQ(r.frictions.size(), 4u);
  EXPECT_EQ(r.frictions[0].static_mu, 0.3);  // the default
  EXPECT_EQ(r.frictions[0].dynamic_mu, 0.3);
  EXPECT_EQ(r.frictions[1].static_mu, 0);
  EXPECT_EQ(r.frictions[2].static_mu, 0.6);
  EXPECT_EQ(r.frictions[2].dynamic_mu, 0.4);
  EXPECT_EQ(r.frictions[3].dynamic_mu, 0.5);
  const auto error = [](const std::string& text) {
    return message_of<ConfigError>([&] { rigid_config(params(text)); });
  };
  EXPECT_EQ(error("bodies: [{name: a, friction: {static: 0.2, dynamic: 0.4}}]\n"),
            "r.yaml:1:53: 'dynamic' friction must not exceed 'static'");
  EXPECT_EQ(error("bodies: [{name: a, friction: {static: 0.2}}]\n"),
            "r.yaml:1:30: 'friction' is missing required key 'dynamic'");
  EXPECT_EQ(error("bodies: [{name: a, friction: -1}]\n"), "r.yaml:1:30: 'friction' = -1 is outside [0, 10]");
}

TEST(RigidConfig, MistakesAreNamedAtTheirPlace) {
  const auto error = [](const std::string& text) {
    return message_of<ConfigError>([&] { rigid_config(params(text)); });
  };
  EXPECT_EQ(error("device: omni\n"), "r.yaml:1:1: hcosim_rigid: params.bodies lists no body; docs/rigid.md");
  EXPECT_EQ(error("bodies: [{name: a}, {name: a}]\n"), "r.yaml:1:28: two bodies are named 'a'");
  EXPECT_EQ(error("bodies: [{name: a, centre: [0, 0, 0.001], size: 0.01}]\n"),
            "r.yaml:1:28: centre z must be at least size: the body would start inside the marker plane (ground: on)");
  EXPECT_EQ(error("bodies: [{name: a, shape: cone}]\n"),
            "r.yaml:1:27: 'shape' must be one of sphere, cube, not 'cone'");
  EXPECT_EQ(error("bodies: [{name: a, colour: red}]\n"),
            "r.yaml:1:20: unknown key 'colour' (valid keys: name, shape, size, mass, centre, velocity, "
            "angular_velocity, friction)");
  EXPECT_EQ(error("stifness: 5\nbodies: [{name: a}]\n"),
            "r.yaml:1:1: unknown key 'stifness'; did you mean 'stiffness'?");
  EXPECT_EQ(error("backend: bullet\nbodies: [{name: a}]\n"),
            "r.yaml:1:10: 'backend' must be one of analytic, mujoco, crosscheck, not 'bullet'");
  EXPECT_EQ(error("bodies: [{shape: cube}]\n"), "r.yaml:1:10: each body needs a name of 1 to 31 characters");
}

}  // namespace
}  // namespace hcosim::adapters::rigid
