// bench tracking: marker detection and pose on synthetic sequences with
// known ground truth (models/vision/synthetic.h): 200 random poses of a
// 5 cm tag36h11 between 0.15 and 0.7 m and up to 55 degrees of tilt, per
// resolution and condition (clean, noisy, blurred).
//
// detect rows, params `detector`, `resolution`, `decimate`, `sigma` (quad_sigma), `condition`:
//   apriltag        hcosim's path: libapriltag, corners refitted to the
//                   border's edges, IPPE pose refined by Levenberg-Marquardt;
//   apriltag_plain  libapriltag with its defaults as most users call it:
//                   its corners as they come (pixel centres at +0.5), IPPE;
//   aruco           OpenCV ArUco, DICT_APRILTAG_36h11, sub-pixel corner
//                   refinement, the same IPPE pose: the baseline.
//   Metrics: ms_per_frame (median of detection plus pose, one thread),
//   detection_rate, trans_err_p95_pct (percent of distance),
//   rot_err_p95_deg, corner_err_p95_px, and the speed ratio to ArUco on the
//   same frames.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <opencv2/aruco.hpp>
#include <opencv2/core/utility.hpp>

#include "models/vision/detector.h"
#include "models/vision/pose.h"
#include "models/vision/synthetic.h"
#include "services/bench/bench.h"

namespace hcosim::services::bench {
namespace {

using namespace hcosim::models::vision;
using Clock = std::chrono::steady_clock;
using Corners = std::array<Eigen::Vector2d, 4>;

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[std::size_t(q * double(v.size() - 1) + 0.5)];
}

// A detector under test: the corners of tag 0 in a frame, if found.
using Detect = std::function<bool(const cv::Mat&, Corners&)>;

struct Candidate {
  std::string name;
  double decimate;
  double sigma;  // quad_sigma, px
  Detect detect;
  PoseOptions pose;
};

std::vector<Candidate> candidates(bool quick) {
  std::vector<Candidate> out;
  // Decimation trades corner-search resolution for speed; a blur before
  // the quad search (quad_sigma) spares the search noise's false edges.
  std::vector<std::pair<double, double>> settings{{1.5, 0}};
  if (!quick) settings = {{1, 0}, {1.5, 0}, {2, 0}, {1.5, 0.8}};
  for (const auto& [dec, sigma] : settings) {
    DetectorParams p;
    p.quad_decimate = dec;
    p.quad_sigma = sigma;
    auto d = std::make_shared<Detector>(p);
    out.push_back({"apriltag", dec, sigma,
                   [d](const cv::Mat& f, Corners& c) {
                     for (const Detection& x : d->detect(f))
                       if (x.id == 0) return c = x.corners, true;
                     return false;
                   },
                   PoseOptions{}});
  }
  DetectorParams plain;
  plain.quad_decimate = 2;  // libapriltag's default
  plain.refine_corners = false;
  auto d = std::make_shared<Detector>(plain);
  out.push_back({"apriltag_plain", plain.quad_decimate, 0,
                 [d](const cv::Mat& f, Corners& c) {
                   for (const Detection& x : d->detect(f))
                     if (x.id == 0) {
                       for (std::size_t k = 0; k < 4; ++k) c[k] = x.corners[k] + Eigen::Vector2d(0.5, 0.5);
                       return true;
                     }
                   return false;
                 },
                 PoseOptions{false, 1.5}});
  auto dict = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_APRILTAG_36h11);
  auto params = cv::aruco::DetectorParameters::create();
  params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  out.push_back({"aruco", 0, 0,
                 [dict, params](const cv::Mat& f, Corners& c) {
                   std::vector<std::vector<cv::Point2f>> corners;
                   std::vector<int> ids;
                   cv::aruco::detectMarkers(f, dict, corners, ids, params);
                   for (std::size_t i = 0; i < ids.size(); ++i)
                     if (ids[i] == 0) {
                       // ArUco runs clockwise on screen from the corner
                       // that is our corner 1 (its copy of the codes is
                       // a half turn from libapriltag's); ours run the
                       // other way.
                       const int order[4] = {1, 0, 3, 2};
                       for (std::size_t k = 0; k < 4; ++k) {
                         const cv::Point2f& p = corners[i][std::size_t(order[k])];
                         c[k] = {p.x, p.y};
                       }
                       return true;
                     }
                   return false;
                 },
                 PoseOptions{}});
  return out;
}

std::vector<Row> tracking_rows(const Context& ctx) {
  cv::setNumThreads(1);  // one core for every detector
  const int n = ctx.quick ? 30 : 200;
  const Marker marker;
  std::vector<Candidate> all = candidates(ctx.quick);
  std::vector<Row> rows;
  for (const cv::Size size :
       ctx.quick ? std::vector<cv::Size>{{640, 480}} : std::vector<cv::Size>{{640, 480}, {1280, 720}}) {
    const Intrinsics k = synthetic_intrinsics(size.width, size.height);
    const SyntheticCamera camera(k, marker);
    const std::vector<Eigen::Isometry3d> poses = random_poses(k, marker.tag_size, n, 7);
    const std::string resolution = std::to_string(size.width) + "x" + std::to_string(size.height);
    for (const std::string condition_name : {"clean", "noisy", "blurred"}) {
      progress("tracking: rendering " + std::to_string(n) + " " + condition_name + " frames at " + resolution);
      std::vector<cv::Mat> frames;
      for (int i = 0; i < n; ++i)
        frames.push_back(camera.render(poses[std::size_t(i)], condition(condition_name), std::uint64_t(i)));
      std::vector<Row> group;
      double aruco_ms = 0;
      for (const Candidate& c : all) {
        progress("tracking: " + c.name +
                 (c.decimate > 0 ? " decimate " + std::to_string(c.decimate).substr(0, 3) : "") +
                 (c.sigma > 0 ? " sigma " + std::to_string(c.sigma).substr(0, 3) : "") + ", " + condition_name + " " +
                 resolution);
        std::vector<double> ms, trans, rot, corner;
        int found = 0;
        for (int i = 0; i < n; ++i) {
          const Eigen::Isometry3d& truth = poses[std::size_t(i)];
          Corners got;
          const auto t0 = Clock::now();
          const bool ok = c.detect(frames[std::size_t(i)], got);
          TagPose pose;
          if (ok) pose = estimate_pose(got, marker.tag_size, k, c.pose);
          ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
          if (!ok) continue;
          ++found;
          const std::vector<Eigen::Vector2d> expected = camera.corners(truth);
          for (std::size_t j = 0; j < 4; ++j) corner.push_back((got[j] - expected[j]).norm());
          trans.push_back(100 * (pose.tag_in_camera.translation() - truth.translation()).norm() /
                          truth.translation().norm());
          rot.push_back(angle_between(pose.tag_in_camera.linear(), truth.linear()) * 180 / std::acos(-1.0));
        }
        const double median_ms = percentile(ms, 0.5);
        if (c.name == "aruco") aruco_ms = median_ms;
        group.push_back({"detect",
                         {{"detector", c.name},
                          {"resolution", resolution},
                          {"decimate", c.decimate},
                          {"sigma", c.sigma},
                          {"condition", condition_name}},
                         {{"ms_per_frame", median_ms},
                          {"detection_rate", double(found) / n},
                          {"trans_err_p95_pct", percentile(trans, 0.95)},
                          {"rot_err_p95_deg", percentile(rot, 0.95)},
                          {"corner_err_p95_px", percentile(corner, 0.95)},
                          {"frames", double(n)}}});
      }
      for (Row& r : group) {
        r.metrics.push_back({"speed_ratio_to_aruco", r.metrics[0].second / aruco_ms});
        rows.push_back(std::move(r));
      }
    }
  }
  return rows;
}

}  // namespace

Suite tracking_suite() {
  Suite s{"tracking",
          "marker tracking: AprilTag (hcosim's path and plain) against OpenCV ArUco on synthetic sequences with ground "
          "truth",
          tracking_rows};
  s.tables = {{"detect",
               "Random poses of a 5 cm tag36h11 between 0.15 and 0.7 m and up to 55 degrees of tilt, rendered with "
               "known pose (clean, noisy, blurred): median ms per frame for detection plus pose on one thread, and "
               "95th-percentile errors against the truth; apriltag is hcosim's path (edge-refitted corners, refined "
               "IPPE), apriltag_plain libapriltag as most call it, aruco OpenCV's detector on the same frames, the "
               "baseline of speed_ratio_to_aruco."}};
  s.plots = {{"detect",
              "ms_per_frame",
              "trans_err_p95_pct",
              "ms per frame (median)",
              "translation error p95 (% of distance)",
              {"detector", "decimate", "sigma"},
              {"resolution", "condition"},
              {"detector", "aruco"}}};
  s.goals = {{"hcosim's path within 0.2% of the distance (p95) on every sequence", "detect", "trans_err_p95_pct", 0.2,
              "detector", "apriltag"},
             {"hcosim's path within 0.4 deg (p95) on every sequence", "detect", "rot_err_p95_deg", 0.4, "detector",
              "apriltag"}};
  return s;
}

}  // namespace hcosim::services::bench
