#include "adapters/vision/vision_idl.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "adapters/validate.h"

namespace hcosim::adapters::vision {

Transform to_idl(const Eigen::Isometry3d& pose) {
  Transform t;
  const Eigen::Vector3d p = pose.translation();
  const Eigen::Quaterniond q(pose.linear());
  t.position().x(p.x()), t.position().y(p.y()), t.position().z(p.z());
  t.orientation().w(q.w()), t.orientation().x(q.x()), t.orientation().y(q.y()), t.orientation().z(q.z());
  return t;
}

Eigen::Matrix3d from_idl(const Quat& q) {
  return Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).normalized().toRotationMatrix();
}

Eigen::Isometry3d from_idl(const Transform& t) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(t.position().x(), t.position().y(), t.position().z());
  p.linear() = from_idl(t.orientation());
  return p;
}

MarkerPose marker_pose(const std::string& camera, const std::string& family, const StepStamp& stamp,
                       std::uint64_t frame, double tag_size, const models::vision::Observation& o, double latency_ms) {
  MarkerPose m;
  m.camera(camera);
  m.tag_id(o.detection.id);
  m.family(family);
  m.stamp(stamp);
  m.frame(frame);
  m.tag_in_camera(to_idl(o.pose.tag_in_camera));
  m.tag_size_m(tag_size);
  m.reprojection_error_px(o.pose.reprojection_error_px);
  m.decision_margin(o.detection.decision_margin);
  m.latency_ms(latency_ms);
  return m;
}

CameraFrame camera_frame(const std::string& camera, const StepStamp& stamp, std::uint64_t frame, const cv::Mat& image,
                         const models::vision::Intrinsics& k) {
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3)
    throw std::invalid_argument("camera_frame: images must be 8-bit grey or BGR");
  CameraFrame f;
  f.camera(camera);
  f.stamp(stamp);
  f.frame(frame);
  f.width(std::uint32_t(image.cols));
  f.height(std::uint32_t(image.rows));
  f.encoding(image.channels() == 1 ? "mono8" : "bgr8");
  f.fx(k.fx), f.fy(k.fy), f.cx(k.cx), f.cy(k.cy);
  for (std::size_t i = 0; i < 5; ++i) f.distortion()[i] = k.distortion[i];
  // Rows may be padded in a cv::Mat (a region of a larger image): copy row by row.
  const std::size_t row = std::size_t(image.cols) * std::size_t(image.channels());
  f.data().resize(row * std::size_t(image.rows));
  for (int r = 0; r < image.rows; ++r)
    std::copy_n(image.ptr<std::uint8_t>(r), row, f.data().data() + row * std::size_t(r));
  return f;
}

cv::Mat pixels(const CameraFrame& f) {
  if (auto problem = validate(f)) throw std::invalid_argument("camera frame: " + *problem);
  const bool mono = f.encoding().to_string() == "mono8";
  return cv::Mat(int(f.height()), int(f.width()), mono ? CV_8UC1 : CV_8UC3, const_cast<std::uint8_t*>(f.data().data()));
}

cv::Mat bgr_image(const CameraFrame& f) {
  const cv::Mat wrapped = pixels(f);
  cv::Mat bgr;
  if (wrapped.channels() == 1)
    cv::cvtColor(wrapped, bgr, cv::COLOR_GRAY2BGR);
  else
    bgr = wrapped.clone();
  return bgr;
}

models::vision::Intrinsics intrinsics(const CameraFrame& f) {
  models::vision::Intrinsics k;
  k.width = int(f.width()), k.height = int(f.height());
  k.fx = f.fx(), k.fy = f.fy(), k.cx = f.cx(), k.cy = f.cy();
  for (int i = 0; i < 5; ++i) k.distortion[std::size_t(i)] = f.distortion()[std::size_t(i)];
  models::vision::check(k);
  return k;
}

}  // namespace hcosim::adapters::vision
