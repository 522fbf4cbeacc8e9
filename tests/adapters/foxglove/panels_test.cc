// Foxglove's scene channels from the topics, read back from their CDR with
// the generated Foxglove types: a mesh keeps its vertices and triangles, a
// body stands at its pose, the stylus shows at its rate with its force as
// an arrow, the camera sits where the marker says, frames are JPEGs.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "adapters/foxglove/panels.h"
#include "adapters/vision/vision_idl.h"
#include "idl/foxglove.h"
#include "idl/foxglovePubSubTypes.h"

namespace hcosim::adapters::foxglove {
namespace {

template <class PubSub, class T>
T read(const Message& m) {
  PubSub type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(std::uint32_t(m.cdr.size()));
  std::copy(m.cdr.begin(), m.cdr.end(), payload.data);
  payload.length = std::uint32_t(m.cdr.size());
  T out;
  EXPECT_TRUE(type.deserialize(&payload, &out));
  return out;
}

::foxglove::SceneUpdate update(const Message& m) {
  EXPECT_STREQ(m.schema, "foxglove::SceneUpdate");
  return read<::foxglove::SceneUpdatePubSubType, ::foxglove::SceneUpdate>(m);
}

StepStamp stamp(std::int64_t sim_ns) {
  StepStamp s;
  s.step(std::uint64_t(sim_ns / 1000000));
  s.sim_time_ns(sim_ns);
  s.wall_time_ns(1700000000123456789 + sim_ns);
  return s;
}

TEST(Panels, AMeshIsItsVerticesAndTrianglesOnceItsTopologyIsKnown) {
  Builder b({{"sheet", "deformable", 0}});
  DeformedMesh m;
  m.mesh("sheet");
  m.stamp(stamp(0));
  m.topology_version(1);
  m.positions({0, 0, 0, 0.01f, 0, 0, 0, 0.02f, 0.005f, 0.01f, 0.02f, 0});
  EXPECT_TRUE(b.on(m).empty());
  EXPECT_EQ(b.unmatched(), 1u);
  MeshTopology t;
  t.mesh("sheet");
  t.topology_version(1);
  t.vertex_count(4);
  t.triangles({0, 1, 2, 1, 3, 2});
  EXPECT_TRUE(b.on(t).empty());
  const std::vector<Message> out = b.on(m);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic, "scene/sheet");
  const ::foxglove::SceneUpdate u = update(out[0]);
  ASSERT_EQ(u.entities().size(), 1u);
  const ::foxglove::SceneEntity& e = u.entities()[0];
  EXPECT_EQ(e.id(), "sheet");
  EXPECT_EQ(e.frame_id(), "world");
  EXPECT_EQ(e.timestamp().sec(), 1700000000u);
  EXPECT_EQ(e.timestamp().nsec(), 123456789u);
  ASSERT_EQ(e.triangles().size(), 1u);
  const ::foxglove::TriangleListPrimitive& tl = e.triangles()[0];
  ASSERT_EQ(tl.points().size(), 4u);
  EXPECT_EQ(tl.points()[2].y(), double(0.02f));
  EXPECT_EQ(tl.points()[2].z(), double(0.005f));
  EXPECT_EQ(tl.indices(), (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(tl.color().a(), 1.0);
  // Another version's mesh waits for its topology.
  m.topology_version(2);
  EXPECT_TRUE(b.on(m).empty());
  EXPECT_EQ(b.unmatched(), 2u);
}

TEST(Panels, ARigidBodyStandsAtItsPoseAtTheSceneRate) {
  Builder b({{"box", "rigid", 0.01}}, Options{});
  RigidBodyState s;
  s.body("box");
  s.shape("cube");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.1, -0.2, 0.03);
  pose.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  s.pose(vision::to_idl(pose));
  int shown = 0;
  for (int ms = 0; ms < 1000; ++ms) {
    s.stamp(stamp(std::int64_t(ms) * 1000000));
    for (const Message& m : b.on(s)) {
      ++shown;
      const ::foxglove::SceneUpdate u = update(m);
      const ::foxglove::TriangleListPrimitive& t = u.entities()[0].triangles()[0];
      EXPECT_EQ(t.points().size(), 24u);  // the AR view's cube: flat faces
      EXPECT_DOUBLE_EQ(t.pose().position().x(), 0.1);
      EXPECT_NEAR(t.pose().orientation().z(), std::sin(0.25), 1e-12);
      EXPECT_NEAR(std::abs(t.points()[0].x()), 0.01, 1e-12);
    }
  }
  EXPECT_EQ(shown, 60);
  // A body the deployment does not size is not drawn.
  s.body("other");
  EXPECT_TRUE(b.on(s).empty());
}

TEST(Panels, TheStylusShowsItsForceAsAnArrowAlongIt) {
  Options o;
  o.force_scale = 0.02;
  Builder b({}, o);
  HapticState h;
  h.device("omni");
  h.stamp(stamp(0));
  h.position().x(0.01), h.position().z(0.03);
  h.orientation().w(1);
  h.rendered_force().y(0.6), h.rendered_force().z(0.8);  // 1 N
  const std::vector<Message> out = b.on(h);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic, "scene/stylus");
  const ::foxglove::SceneEntity e = update(out[0]).entities()[0];
  ASSERT_EQ(e.arrows().size(), 1u);
  const ::foxglove::ArrowPrimitive& a = e.arrows()[0];
  EXPECT_NEAR(a.shaft_length() + a.head_length(), 0.02, 1e-12);
  EXPECT_DOUBLE_EQ(a.pose().position().z(), 0.03);
  const ::foxglove::Quaternion& q = a.pose().orientation();
  const Eigen::Vector3d along = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(along.y(), 0.6, 1e-12);
  EXPECT_NEAR(along.z(), 0.8, 1e-12);
  ASSERT_EQ(e.cylinders().size(), 1u);
  EXPECT_GT(e.cylinders()[0].pose().position().z(), 0.03);  // the pen above the tip
  // The next state within 1/60 s gives nothing; a force under 0.01 N no arrow.
  h.stamp(stamp(1000000));
  EXPECT_TRUE(b.on(h).empty());
  h.stamp(stamp(17000000));
  h.rendered_force().y(0), h.rendered_force().z(0.005);
  const std::vector<Message> next = b.on(h);
  ASSERT_EQ(next.size(), 1u);
  EXPECT_TRUE(update(next[0]).entities()[0].arrows().empty());
}

TEST(Panels, TheCameraSitsWhereTheMarkerSeenFromItSays) {
  Builder b({});
  MarkerPose p;
  p.camera("cam");
  p.tag_id(0);
  p.stamp(stamp(0));
  Eigen::Isometry3d tag_in_camera = Eigen::Isometry3d::Identity();
  tag_in_camera.translation() = Eigen::Vector3d(0, 0, 0.3);  // 30 cm ahead
  tag_in_camera.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  p.tag_in_camera(vision::to_idl(tag_in_camera));
  const std::vector<Message> out = b.on(p);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic, "tf");
  EXPECT_STREQ(out[0].schema, "foxglove::FrameTransforms");
  const auto tf = read<::foxglove::FrameTransformsPubSubType, ::foxglove::FrameTransforms>(out[0]);
  ASSERT_EQ(tf.transforms().size(), 1u);
  const ::foxglove::FrameTransform& t = tf.transforms()[0];
  EXPECT_EQ(t.parent_frame_id(), "world");
  EXPECT_EQ(t.child_frame_id(), "cam");
  // Facing the tag from 30 cm: the camera is 30 cm above it, in the world.
  EXPECT_NEAR(t.translation().z(), 0.3, 1e-12);
  EXPECT_NEAR(t.translation().x(), 0, 1e-12);
  p.tag_id(3);  // another marker is not the world's
  EXPECT_TRUE(b.on(p).empty());
}

TEST(Panels, ACameraFrameIsAJpegOfItsPixels) {
  Builder b({});
  CameraFrame f;
  f.camera("cam");
  f.stamp(stamp(0));
  f.width(64), f.height(48);
  f.encoding("bgr8");
  f.fx(80), f.fy(80), f.cx(32), f.cy(24);
  std::vector<std::uint8_t> pixels(64 * 48 * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = std::uint8_t(i % 3 == 2 ? 200 : 40);  // red
  f.data(pixels);
  const std::vector<Message> out = b.on(f);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic, "image/cam");
  const auto image = read<::foxglove::CompressedImagePubSubType, ::foxglove::CompressedImage>(out[0]);
  EXPECT_EQ(image.format(), "jpeg");
  EXPECT_EQ(image.frame_id(), "cam");
  const cv::Mat back = cv::imdecode(image.data(), cv::IMREAD_COLOR);
  ASSERT_EQ(back.cols, 64);
  const cv::Vec3b centre = back.at<cv::Vec3b>(24, 32);
  EXPECT_NEAR(centre[2], 200, 8);
  EXPECT_NEAR(centre[0], 40, 8);
}

TEST(Panels, BadOptionsAndUnsizedBodiesAreRefused) {
  Options o;
  o.rate_hz = 0;
  EXPECT_THROW(Builder({}, o), std::invalid_argument);
  o = Options{};
  o.jpeg_quality = 101;
  EXPECT_THROW(Builder({}, o), std::invalid_argument);
  EXPECT_THROW(Builder({{"box", "rigid", 0}}), std::invalid_argument);
}

TEST(Panels, TheSchemaTextDeclaresEveryRootType) {
  const std::string text = schema_text();
  for (const char* root : {"struct SceneUpdate {", "struct FrameTransforms {", "struct CompressedImage {"})
    EXPECT_NE(text.find(root), std::string::npos) << root;
  EXPECT_EQ(text.find("#include"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::adapters::foxglove
