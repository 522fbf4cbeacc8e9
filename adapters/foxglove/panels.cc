#include "adapters/foxglove/panels.h"

#include <stdexcept>

#include <Eigen/Geometry>

#include "adapters/device/haptic_idl.h"
#include "adapters/render/ar_idl.h"
#include "adapters/vision/media.h"
#include "adapters/vision/vision_idl.h"
#include "idl/foxglove.h"
#include "idl/foxglovePubSubTypes.h"
#include "idl/schemas.h"
#include "models/render/view.h"

namespace hcosim::adapters::foxglove {

namespace {

constexpr const char* kSceneUpdate = "foxglove::SceneUpdate";
constexpr const char* kFrameTransforms = "foxglove::FrameTransforms";
constexpr const char* kCompressedImage = "foxglove::CompressedImage";
constexpr double kLeastForce = 0.01;  // N: as the AR view, smaller forces draw no arrow

// A message's classic CDR, as a DDS writer would put it on the wire. The
// type support is made once a thread: its constructor walks every nested
// sequence at fastddsgen's default bound for the largest size (a
// SceneUpdate's took most of a live bridge's CPU, bench foxglove).
template <class PubSub, class T>
std::vector<std::uint8_t> cdr(const T& m) {
  static thread_local PubSub type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(const_cast<T*>(&m))());
  if (!type.serialize(const_cast<T*>(&m), &payload)) throw std::runtime_error("cannot serialize a Foxglove message");
  return {payload.data, payload.data + payload.length};
}

::foxglove::Time time_of(const StepStamp& s) {
  ::foxglove::Time t;
  const std::int64_t ns = std::max<std::int64_t>(s.wall_time_ns(), 0);
  t.sec(std::uint32_t(ns / 1000000000));
  t.nsec(std::uint32_t(ns % 1000000000));
  return t;
}

::foxglove::Vector3 vector(const Eigen::Vector3d& v) {
  ::foxglove::Vector3 out;
  out.x(v.x()), out.y(v.y()), out.z(v.z());
  return out;
}

::foxglove::Quaternion quaternion(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  ::foxglove::Quaternion out;
  out.x(q.x()), out.y(q.y()), out.z(q.z()), out.w(q.w());
  return out;
}

::foxglove::Pose3 pose(const Eigen::Vector3d& position, const Eigen::Matrix3d& orientation) {
  ::foxglove::Pose3 p;
  p.position(vector(position));
  p.orientation(quaternion(orientation));
  return p;
}

// The AR view's colour of the i-th object, BGR 0..255 there, RGB 0..1 here.
::foxglove::ColorRGBA colour(std::size_t i, double alpha = 1) {
  const cv::Scalar bgr = models::render::object_colour(i);
  ::foxglove::ColorRGBA c;
  c.r(bgr[2] / 255), c.g(bgr[1] / 255), c.b(bgr[0] / 255), c.a(alpha);
  return c;
}

::foxglove::ColorRGBA rgba(double r, double g, double b, double a = 1) {
  ::foxglove::ColorRGBA c;
  c.r(r), c.g(g), c.b(b), c.a(a);
  return c;
}

// A triangle list of `m`, its points `m`'s vertices in the frame of `at`.
::foxglove::TriangleListPrimitive triangles(const models::render::Mesh& m, const ::foxglove::Pose3& at,
                                            const ::foxglove::ColorRGBA& c) {
  ::foxglove::TriangleListPrimitive t;
  t.pose(at);
  std::vector<::foxglove::Point3>& points = t.points();
  points.resize(std::size_t(m.vertices.cols()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto v = m.vertices.col(Eigen::Index(i));
    points[i].x(v.x()), points[i].y(v.y()), points[i].z(v.z());
  }
  t.color(c);
  t.indices().assign(m.triangles.begin(), m.triangles.end());
  return t;
}

::foxglove::SceneEntity entity(const StepStamp& stamp, const std::string& id) {
  ::foxglove::SceneEntity e;
  e.timestamp(time_of(stamp));
  e.frame_id("world");
  e.id(id);
  return e;
}

Message scene_message(const ChannelOf& c, ::foxglove::SceneEntity e) {
  ::foxglove::SceneUpdate u;
  u.entities().push_back(std::move(e));
  return {c.topic, c.schema, cdr<::foxglove::SceneUpdatePubSubType>(u)};
}

bool drawn_shape(const std::string& shape) { return shape == "cube" || shape == "sphere"; }

}  // namespace

const char* schema_text() {
  for (const idl::IdlText& f : idl::kIdlTexts)
    if (std::string(f.file) == "foxglove") return f.text;
  throw std::logic_error("idl/foxglove.idl is not among the generated schemas");
}

Builder::Builder(std::vector<Item> items, Options o) : options_(o), items_(std::move(items)) {
  if (!(o.rate_hz > 0 && o.rate_hz <= 1e4)) throw std::invalid_argument("scene rate must be in (0, 10000] Hz");
  if (o.jpeg_quality < 0 || o.jpeg_quality > 100) throw std::invalid_argument("JPEG quality must be 0..100");
  if (!(o.force_scale >= 0)) throw std::invalid_argument("force scale must be >= 0");
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const Item& it = items_[i];
    colours_[it.name] = i;
    if (it.kind != "rigid") continue;
    if (!(it.size > 0)) throw std::invalid_argument("rigid item '" + it.name + "' needs a size > 0");
    // Shape unknown until its first state: both kept, one drawn.
    bodies_[it.name].colour = i;
  }
}

bool Builder::due(std::int64_t& next_ns, std::int64_t sim_time_ns) const {
  if (sim_time_ns < next_ns) return false;
  // From the last due time, so that 1 ms steps keep the rate on average;
  // from now after a gap.
  const std::int64_t period = std::int64_t(1e9 / options_.rate_hz);
  next_ns = next_ns + period > sim_time_ns ? next_ns + period : sim_time_ns + period;
  return true;
}

std::size_t Builder::colour_of(const std::string& name) {
  return colours_.emplace(name, colours_.size()).first->second;
}

ChannelOf Builder::channel(const DeformedMesh& m) const { return {"scene/" + m.mesh().to_string(), kSceneUpdate}; }

ChannelOf Builder::channel(const RigidBodyState& s) const {
  const std::string name = s.body().to_string();
  for (const Item& it : items_)
    if (it.name == name && it.kind == "rigid" && drawn_shape(s.shape().to_string()))
      return {"scene/" + name, kSceneUpdate};
  return {};
}

ChannelOf Builder::channel(const HapticState&) const { return {"scene/stylus", kSceneUpdate}; }

ChannelOf Builder::channel(const MarkerPose& p) const {
  if (p.tag_id() != options_.tag_id) return {};
  return {"tf", kFrameTransforms};
}

ChannelOf Builder::channel(const CameraFrame& f) const { return {"image/" + f.camera().to_string(), kCompressedImage}; }

std::vector<Message> Builder::on(const MeshTopology& t) {
  topology_[t.mesh().to_string()] = t;
  return {};
}

std::vector<Message> Builder::on(const DeformedMesh& m) {
  const std::string name = m.mesh().to_string();
  const auto t = topology_.find(name);
  models::render::Mesh mesh;
  try {
    if (t == topology_.end()) throw std::invalid_argument("no topology");
    mesh = render::mesh(m, t->second);
  } catch (const std::invalid_argument&) {
    return ++unmatched_, std::vector<Message>{};
  }
  ::foxglove::SceneEntity e = entity(m.stamp(), name);
  e.triangles().push_back(
      triangles(mesh, pose(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity()), colour(colour_of(name))));
  return {scene_message(channel(m), std::move(e))};
}

std::vector<Message> Builder::on(const RigidBodyState& s) {
  const auto b = bodies_.find(s.body().to_string());
  if (b == bodies_.end() || !due(b->second.next_ns, s.stamp().sim_time_ns())) return {};
  const std::string shape = s.shape().to_string();
  if (!drawn_shape(shape)) return {};
  Body& body = b->second;
  if (body.shape.vertices.cols() == 0) {
    double size = 0;
    for (const Item& it : items_)
      if (it.name == b->first) size = it.size;
    body.shape = shape == "cube" ? models::render::cube(size) : models::render::sphere(size);
  }
  const Eigen::Isometry3d at = vision::from_idl(s.pose());
  ::foxglove::SceneEntity e = entity(s.stamp(), b->first);
  e.triangles().push_back(triangles(body.shape, pose(at.translation(), at.linear()), colour(body.colour)));
  return {scene_message(channel(s), std::move(e))};
}

std::vector<Message> Builder::on(const HapticState& s) {
  if (!due(stylus_next_ns_, s.stamp().sim_time_ns())) return {};
  const models::render::View look;  // the AR view's stylus sizes
  const Eigen::Vector3d tip = device::from_idl(s.position());
  const Eigen::Matrix3d r = vision::from_idl(s.orientation());
  ::foxglove::SceneEntity e = entity(s.stamp(), "stylus");
  // The pen runs along +z from the tip; a cylinder's pose is its centre.
  ::foxglove::CylinderPrimitive pen;
  pen.pose(pose(tip + r * Eigen::Vector3d(0, 0, look.stylus_length / 2), r));
  pen.size(vector({2 * look.stylus_radius, 2 * look.stylus_radius, look.stylus_length}));
  pen.bottom_scale(1), pen.top_scale(1);
  pen.color(rgba(0.85, 0.85, 0.85));
  e.cylinders().push_back(pen);
  ::foxglove::SpherePrimitive ball;
  ball.pose(pose(tip, r));
  ball.size(vector(Eigen::Vector3d::Constant(3 * look.stylus_radius)));
  ball.color(rgba(1, 0.85, 0.2));
  e.spheres().push_back(ball);
  const Eigen::Vector3d f = device::from_idl(s.rendered_force());
  if (f.norm() >= kLeastForce && options_.force_scale > 0) {
    // An arrow points along its +x: the rotation taking x to the force.
    const double length = options_.force_scale * f.norm();
    ::foxglove::ArrowPrimitive a;
    a.pose(pose(tip, Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), f).toRotationMatrix()));
    a.head_length(std::min(0.3 * length, 0.006));
    a.shaft_length(length - a.head_length());
    a.shaft_diameter(0.0015);
    a.head_diameter(0.004);
    a.color(rgba(1, 0.2, 0.2));
    e.arrows().push_back(a);
  }
  return {scene_message(channel(s), std::move(e))};
}

std::vector<Message> Builder::on(const MarkerPose& p) {
  const ChannelOf c = channel(p);
  if (c.topic.empty()) return {};
  // The topic gives the tag in the camera; the tree wants the camera in the
  // world, which is the tag's frame.
  const Eigen::Isometry3d camera_in_world = vision::from_idl(p.tag_in_camera()).inverse();
  ::foxglove::FrameTransform t;
  t.timestamp(time_of(p.stamp()));
  t.parent_frame_id("world");
  t.child_frame_id(p.camera().to_string());
  t.translation(vector(camera_in_world.translation()));
  t.rotation(quaternion(camera_in_world.linear()));
  ::foxglove::FrameTransforms all;
  all.transforms().push_back(t);
  return {{c.topic, c.schema, cdr<::foxglove::FrameTransformsPubSubType>(all)}};
}

std::vector<Message> Builder::on(const CameraFrame& f) {
  ::foxglove::CompressedImage image;
  image.timestamp(time_of(f.stamp()));
  image.frame_id(f.camera().to_string());
  const std::vector<unsigned char> jpeg = vision::encode_jpeg(vision::pixels(f), options_.jpeg_quality);
  image.data().assign(jpeg.begin(), jpeg.end());
  image.format("jpeg");
  const ChannelOf c = channel(f);
  return {{c.topic, c.schema, cdr<::foxglove::CompressedImagePubSubType>(image)}};
}

}  // namespace hcosim::adapters::foxglove
