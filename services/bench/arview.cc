// bench arview: the AR view's cost per camera frame, against OpenCV drawing
// the same triangles itself, on the default deployment's camera orbit
// (deploy/default.yaml) over its synthetic frames.
//
// frame rows, params `scene` and `resolution`:
//   one_mesh     one hybrid object's visual mesh (rounded box, 5402
//                vertices, 10800 triangles: a 10k-triangle mesh);
//   default      every object of deploy/default.yaml at rest, the stylus
//                and a force arrow (two 10800-triangle meshes, the sheet,
//                the semi-sphere, a cube and a sphere);
//   dense        a 120000-triangle mesh (100 subdivisions).
//   Metrics: draw_ms_p50 and _p99 (the frame converted to BGR and the
//   scene drawn with the depth test), encode_ms_p50 (one MPEG-4 frame,
//   OpenCV's VideoWriter), frame_ms_p50 (both), fps_p50 (1000 over it),
//   opencv_ms_p50 (the baseline: the same triangles, same shading, sorted
//   far to near and filled by cv::fillConvexPoly, no depth buffer), and
//   ratio_to_opencv (draw over baseline, medians of the same frames), and
//   differ_pct: the share of pixels where the two pictures differ by more
//   than 40 grey levels in a channel (edges rasterised apart, and where
//   painting far to near gets the order wrong): that both drew the same
//   scene.
//   A frame is in time at 30 fps when frame_ms stays under 33.3.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "models/deformable/elastic_surface.h"
#include "models/deformable/hybrid.h"
#include "models/deformable/surface.h"
#include "models/render/view.h"
#include "models/vision/synthetic.h"
#include "services/bench/bench.h"

namespace hcosim::services::bench {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

models::render::Mesh from(const models::massspring::TriangleMesh& m) {
  models::render::Mesh out{m.vertices, {}};
  for (const Eigen::Vector3i& t : m.triangles)
    for (int k = 0; k < 3; ++k) out.triangles.push_back(std::uint32_t(t[k]));
  return out;
}

models::render::Mesh box(int subdivisions, const Eigen::Vector3d& centre, double size, double exponent) {
  const Eigen::Vector3d h = Eigen::Vector3d::Constant(size / 2);
  return from(models::deformable::rounded_box(subdivisions, centre - h, centre + h, exponent));
}

models::render::Mesh surface(models::deformable::Shape shape, const Eigen::Vector3d& centre, double size) {
  models::deformable::SurfaceSpec s;
  s.shape = shape;
  s.centre = centre;
  s.size = size;
  const models::deformable::ElasticSurface e(s);
  models::render::Mesh out{e.surface(), {}};
  for (const Eigen::Vector3i& t : e.triangles())
    for (int k = 0; k < 3; ++k) out.triangles.push_back(std::uint32_t(t[k]));
  return out;
}

// deploy/default.yaml's objects at rest, and the stylus pressing the sheet.
models::render::View scene(const std::string& name) {
  models::render::View v;
  const auto add = [&](models::render::Mesh m) {
    v.objects.push_back({"", std::move(m), models::render::object_colour(v.objects.size())});
  };
  if (name == "one_mesh") return add(box(30, {0, 0.035, 0.015}, 0.03, 8)), v;
  if (name == "dense") return add(box(100, {0, 0.035, 0.015}, 0.03, 8)), v;
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.translation() = Eigen::Vector3d(-0.05, 0.035, 0.012);
  add(models::render::placed(models::render::cube(0.012), at));
  at.translation() = Eigen::Vector3d(-0.05, -0.035, 0.012);
  add(models::render::placed(models::render::sphere(0.012), at));
  add(surface(models::deformable::Shape::sheet, {0, 0.04, 0.02}, 0.04));
  add(surface(models::deformable::Shape::semisphere, {0, -0.04, 0}, 0.02));
  add(box(30, {0.05, 0.035, 0.015}, 0.03, 8));
  models::deformable::HybridSpec organ;  // the liver
  organ.shape = models::massspring::read_obj(HCOSIM_LIVER_OBJ);
  organ.size = 0.045, organ.centre = Eigen::Vector3d(0.05, -0.035, 0.0075);
  add(from(models::deformable::hybrid_visual(organ)));
  models::render::Stylus s;
  s.tip = Eigen::Vector3d(0, 0.04, 0.015);
  s.force = Eigen::Vector3d(0, 0, 0.8);
  v.stylus = s;
  return v;
}

std::size_t triangles(const models::render::View& v) {
  std::size_t n = 0;
  for (const models::render::Object& o : v.objects) n += o.mesh.triangles.size() / 3;
  return n;
}

// The baseline: the same shaded triangles painted far to near by OpenCV.
void painter(const models::render::View& v, const models::vision::Intrinsics& k,
             const Eigen::Isometry3d& world_in_camera, cv::Mat& img) {
  struct Tri {
    double depth;
    std::array<cv::Point, 3> px;
    cv::Scalar colour;
  };
  std::vector<Tri> tris;
  for (const models::render::Object& o : v.objects) {
    const Eigen::Matrix3Xd cam = world_in_camera * o.mesh.vertices;
    for (std::size_t t = 0; t < o.mesh.triangles.size(); t += 3) {
      Tri tri;
      Eigen::Vector3d p[3];
      for (int j = 0; j < 3; ++j) {
        p[j] = cam.col(o.mesh.triangles[t + std::size_t(j)]);
        tri.px[std::size_t(j)] = cv::Point(int(std::lround(k.fx * p[j].x() / p[j].z() + k.cx)),
                                           int(std::lround(k.fy * p[j].y() / p[j].z() + k.cy)));
      }
      const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]), c = (p[0] + p[1] + p[2]) / 3;
      if (n.norm() < 1e-15) continue;
      const double shade = 0.35 + 0.65 * std::abs(n.normalized().dot(c.normalized()));
      tri.depth = c.z();
      tri.colour = o.colour * shade;
      tris.push_back(tri);
    }
  }
  std::sort(tris.begin(), tris.end(), [](const Tri& a, const Tri& b) { return a.depth > b.depth; });
  for (const Tri& t : tris) cv::fillConvexPoly(img, t.px.data(), 3, t.colour);
}

std::vector<Row> frame_rows(const Context& c) {
  std::vector<Row> rows;
  const int frames = c.quick ? 30 : 150;
  models::vision::Orbit orbit;
  orbit.upright = true, orbit.distance = 0.3, orbit.swing = 0.02, orbit.base_tilt_deg = 40, orbit.tilt_deg = 10;
  orbit.sweep_deg = 25, orbit.period = 40;
  models::vision::Marker marker;
  marker.tag_size = 0.03, marker.sheet = 8;
  struct Case {
    std::string scene;
    int width, height;
  };
  std::vector<Case> cases{{"one_mesh", 640, 480}, {"default", 640, 480}};
  if (!c.quick) cases.insert(cases.end(), {{"default", 1280, 720}, {"dense", 640, 480}});
  for (const Case& cs : cases) {
    const models::render::View view = scene(cs.scene);
    const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(cs.width, cs.height);
    const models::vision::SyntheticCamera camera(k, marker);
    progress("arview " + cs.scene + " " + std::to_string(cs.width) + "x" + std::to_string(cs.height) + ": " +
             std::to_string(triangles(view)) + " triangles, " + std::to_string(frames) + " frames");
    // Backgrounds rendered ahead (the tracker's work, not the view's).
    std::vector<cv::Mat> grey;
    std::vector<Eigen::Isometry3d> poses;
    for (int i = 0; i < 10; ++i) {
      poses.push_back(models::vision::orbit(2.0 * i, orbit));
      grey.push_back(camera.render(poses.back()));
    }
    const std::string video_path = (c.work / "arview_bench.mp4").string();
    cv::VideoWriter video(video_path, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), 30, cv::Size(cs.width, cs.height));
    if (!video.isOpened()) throw std::runtime_error("bench arview: OpenCV cannot write MPEG-4 video to " + video_path);
    const std::size_t n = std::size_t(frames);
    runtime::Window draw(n), encode(n), total(n), baseline(n), differ(n);
    for (int i = 0; i < frames; ++i) {
      const std::size_t b = std::size_t(i) % grey.size();
      const Clock::time_point t0 = Clock::now();
      cv::Mat img;
      cv::cvtColor(grey[b], img, cv::COLOR_GRAY2BGR);
      models::render::Canvas canvas(img, k, poses[b]);
      models::render::draw(view, canvas);
      draw.add(ms_since(t0));
      const Clock::time_point t1 = Clock::now();
      video.write(img);
      encode.add(ms_since(t1));
      total.add(ms_since(t0));
      const Clock::time_point t2 = Clock::now();
      cv::Mat ref;
      cv::cvtColor(grey[b], ref, cv::COLOR_GRAY2BGR);
      painter(view, k, poses[b], ref);
      baseline.add(ms_since(t2));
      cv::Mat diff, far;
      cv::absdiff(img, ref, diff);
      cv::inRange(diff, cv::Scalar(0, 0, 0), cv::Scalar(40, 40, 40), far);
      differ.add(100.0 * double(far.total() - std::size_t(cv::countNonZero(far))) / double(far.total()));
    }
    video.release();
    std::filesystem::remove(video_path);
    Row r{
        "frame", {{"scene", cs.scene}, {"resolution", std::to_string(cs.width) + "x" + std::to_string(cs.height)}}, {}};
    const double frame_ms = total.percentile(0.5);
    r.metrics = {{"triangles", double(triangles(view))},
                 {"draw_ms_p50", draw.percentile(0.5)},
                 {"draw_ms_p99", draw.percentile(0.99)},
                 {"encode_ms_p50", encode.percentile(0.5)},
                 {"frame_ms_p50", frame_ms},
                 {"frame_ms_p99", total.percentile(0.99)},
                 {"fps_p50", 1000 / frame_ms},
                 {"opencv_ms_p50", baseline.percentile(0.5)},
                 {"ratio_to_opencv", draw.percentile(0.5) / baseline.percentile(0.5)},
                 {"differ_pct", differ.percentile(0.5)}};
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

Suite arview_suite() {
  Suite s{"arview", "the AR view's drawing and video cost per camera frame, against OpenCV's own triangle fill",
          frame_rows};
  s.tables = {{"frame",
               "The AR view drawing each scene over the default deployment's synthetic camera frames: draw, MPEG-4 "
               "encode and both per frame (p50, p99 over the frames), against OpenCV filling the same shaded "
               "triangles far to near on the same frames (the baseline of ratio_to_opencv); differ_pct is the share "
               "of pixels where the two pictures differ, that both drew the same scene."}};
  s.goals = {{"a 10k-triangle mesh drawn and encoded within a 30 fps frame at p99", "frame", "frame_ms_p99",
              1000.0 / 30, "scene", "one_mesh"}};
  return s;
}

}  // namespace hcosim::services::bench
