#include "models/vision/pose.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace hcosim::models::vision {

namespace {

Eigen::Isometry3d to_pose(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  cv::cv2eigen(R, r);
  cv::cv2eigen(tvec.reshape(1, 3), t);
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = r, p.translation() = t;
  return p;
}

double rms_error(const std::vector<cv::Point3d>& obj, const std::vector<cv::Point2d>& img, const cv::Mat& rvec,
                 const cv::Mat& tvec, const Intrinsics& k) {
  std::vector<cv::Point2d> proj;
  cv::projectPoints(obj, rvec, tvec, camera_matrix(k), distortion(k), proj);
  double sum = 0;
  for (std::size_t i = 0; i < img.size(); ++i) sum += std::pow(cv::norm(proj[i] - img[i]), 2);
  return std::sqrt(sum / double(img.size()));
}

}  // namespace

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

TagPose estimate_pose(const std::array<Eigen::Vector2d, 4>& corners, double tag_size, const Intrinsics& k,
                      const PoseOptions& options, const std::optional<Eigen::Isometry3d>& prior) {
  if (!(tag_size > 0 && std::isfinite(tag_size))) throw std::invalid_argument("pose: tag_size must be > 0");
  for (const Eigen::Vector2d& c : corners)
    if (!c.allFinite()) throw std::invalid_argument("pose: a corner is not finite");
  // IPPE_SQUARE wants its object points as (-h, h), (h, h), (h, -h),
  // (-h, -h): our corners 3, 2, 1, 0.
  const double h = 0.5 * tag_size;
  const std::vector<cv::Point3d> obj{{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
  std::vector<cv::Point2d> img;
  for (int i : {3, 2, 1, 0}) img.emplace_back(corners[std::size_t(i)].x(), corners[std::size_t(i)].y());
  std::vector<cv::Mat> rvecs, tvecs;
  cv::Mat errors;
  int n = cv::solvePnPGeneric(obj, img, camera_matrix(k), distortion(k), rvecs, tvecs, false, cv::SOLVEPNP_IPPE_SQUARE,
                              cv::noArray(), cv::noArray(), errors);
  // OpenCV 4.6's IPPE returns NaN for a square seen exactly head-on and
  // centred on the principal point (a synthetic camera's first frame);
  // such a view has one pose, which SQPnP finds.
  for (int i = n - 1; i >= 0; --i)
    if (!cv::checkRange(rvecs[std::size_t(i)]) || !cv::checkRange(tvecs[std::size_t(i)])) {
      rvecs.erase(rvecs.begin() + i), tvecs.erase(tvecs.begin() + i);
      --n;
    }
  if (n == 0) {
    cv::Mat rvec, tvec;
    if (cv::solvePnP(obj, img, camera_matrix(k), distortion(k), rvec, tvec, false, cv::SOLVEPNP_SQPNP) &&
        cv::checkRange(rvec) && cv::checkRange(tvec))
      rvecs = {rvec}, tvecs = {tvec}, n = 1;
  }
  if (n < 1) throw std::invalid_argument("pose: no pose fits these corners");
  // Each solution refined on its own: refining only the one the prior
  // chose could slide it into the other's basin.
  struct Candidate {
    cv::Mat rvec, tvec;
    double error;
    Eigen::Isometry3d pose;
  };
  std::vector<Candidate> c;
  for (int i = 0; i < n; ++i) {
    cv::Mat rvec = rvecs[std::size_t(i)].clone(), tvec = tvecs[std::size_t(i)].clone();
    if (options.refine)
      cv::solvePnPRefineLM(obj, img, camera_matrix(k), distortion(k), rvec, tvec,
                           cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 20, 1e-10));
    c.push_back({rvec, tvec, rms_error(obj, img, rvec, tvec, k), to_pose(rvec, tvec)});
  }
  std::sort(c.begin(), c.end(), [](const Candidate& a, const Candidate& b) { return a.error < b.error; });
  TagPose out;
  std::size_t pick = 0;
  // Two distinct poses that fit about equally: only the prior can tell.
  out.ambiguous = c.size() > 1 && c[1].error <= options.ambiguity_ratio * std::max(c[0].error, 1e-3) &&
                  angle_between(c[0].pose.linear(), c[1].pose.linear()) > 1e-2;
  if (out.ambiguous && prior)
    pick =
        angle_between(c[1].pose.linear(), prior->linear()) < angle_between(c[0].pose.linear(), prior->linear()) ? 1 : 0;
  out.tag_in_camera = c[pick].pose;
  out.reprojection_error_px = c[pick].error;
  return out;
}

}  // namespace hcosim::models::vision
