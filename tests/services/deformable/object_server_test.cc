// The deformable object service's loop without DDS: a press on the sheet is
// answered in contact while the hybrid cube beside it answers free space,
// and in real time only once while that answer covers the stylus; the
// behavior models advance at their own rate and take the press; each
// object's mesh is its topology's vertices; the closing lines count it all.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "services/deformable/object_server.h"
#include "tests/support/samples.h"
#include "tests/support/temp_dir.h"

namespace hcosim::services::deformable {
namespace {

// A 4 cm sheet at the origin and a small hybrid cube 10 cm beside it.
adapters::deformable::DeformableConfig config() {
  return adapters::deformable::deformable_config(
      adapters::Config::parse("objects:\n"
                              "  - {name: sheet, model: sheet, size: 0.04, centre: [0, 0, 0.02]}\n"
                              "  - {name: cube, size: 0.03, elements: 5, map: trilinear, centre: [0.1, 0, 0.015]}\n",
                              "d.yaml", "params"),
      1e-3);
}

using tests::haptic_state;
using tests::stamp;

std::vector<ForceFeedback> answers(ObjectServer& objects, const HapticState& s) {
  std::vector<ForceFeedback> out;
  objects.answer(s, stamp(s.seq()), [&](ForceFeedback& f) { out.push_back(f); });
  return out;
}

TEST(ObjectServer, APressIsAnsweredAndTakenByTheBehaviorModel) {
  tests::TempDir dir;
  ObjectServer objects(config(), 1e-3, false, dir.path.string(), stderr);
  ASSERT_EQ(objects.size(), 2u);
  const std::vector<Eigen::Matrix3Xd> rest = objects.cages();
  std::vector<ForceFeedback> last;
  // Down through the sheet's middle from 2 mm above to 4 mm below, then held.
  for (std::uint64_t k = 0; k < 400; ++k) {
    const double z = 0.022 - 0.006 * std::min(1.0, k / 200.0);
    last = answers(objects, haptic_state(k, {0.001, 0.002, z}));
    ASSERT_EQ(last.size(), 2u) << "lockstep answers every object every state";
    objects.advance(k * 1e-3);
  }
  EXPECT_EQ(last[0].source().to_string(), "sheet");
  EXPECT_TRUE(last[0].in_contact());
  EXPECT_GT(last[0].force().z(), 0) << "the sheet pushes the stylus back up";
  EXPECT_FALSE(last[1].in_contact()) << "the cube is 10 cm away";
  EXPECT_GT(last[1].valid_radius_m(), 0.05) << "its free-space model covers the stylus that far";
  const std::vector<Eigen::Matrix3Xd> pressed = objects.cages();
  EXPECT_GT((pressed[0] - rest[0]).cwiseAbs().maxCoeff(), 1e-3) << "the sheet sank under the press";
  EXPECT_EQ((pressed[1] - rest[1]).cwiseAbs().maxCoeff(), 0) << "nothing touched the cube";
  const std::vector<MeshTopology> topologies = objects.topologies();
  ASSERT_EQ(topologies.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    DeformedMesh m;
    objects.mesh(k, pressed[k], stamp(400), m);
    EXPECT_EQ(m.mesh(), topologies[k].mesh());
    EXPECT_EQ(m.positions().size(), 3 * std::size_t(topologies[k].vertex_count()));
  }
}

TEST(ObjectServer, InRealTimeAFreeSpaceAnswerIsNotRepeatedWhileItCovers) {
  tests::TempDir dir;
  ObjectServer objects(config(), 1e-3, true, dir.path.string(), stderr);
  const Eigen::Vector3d far(0, 0, 0.3);
  EXPECT_EQ(answers(objects, haptic_state(0, far)).size(), 2u);
  EXPECT_TRUE(answers(objects, haptic_state(1, far)).empty());
  EXPECT_TRUE(answers(objects, haptic_state(2, far)).empty());
  EXPECT_EQ(answers(objects, haptic_state(100, far)).size(), 2u);
  const std::string report = tests::written([&](std::FILE* out) { objects.report(out, "objects", {}); });
  EXPECT_NE(report.find("objects: 4 object-states left to a free-space answer"), std::string::npos) << report;
  EXPECT_NE(report.find("sheet: 0 ticks in contact, max force 0.000 N, 0 meshes published"), std::string::npos)
      << report;
}

}  // namespace
}  // namespace hcosim::services::deformable
