// hcosim track: the marker tracker offline, on a video or an image folder,
// one JSON line per detection; with --truth, its errors against known
// poses. hcosim synth: a synthetic sequence with its truth, to try it on.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "adapters/config.h"
#include "adapters/json.h"
#include "adapters/scene.h"
#include "adapters/vision/calibration.h"
#include "adapters/vision/source.h"
#include "models/vision/tracker.h"
#include "services/cli/cli.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {
namespace {

namespace fs = std::filesystem;
using namespace hcosim::models::vision;

// Frames without a tag are named one by one up to this many, then counted.
constexpr int kNamedMisses = 10;
// Per-frame times and errors kept for the summary's percentiles (a longer
// source is summarised over its last this many frames).
constexpr std::size_t kMaxFrames = 1 << 16;

// {"frame": i, "id": n, "R": [row-major, tag to camera], "t": [m], "reprojection_error_px": e}
std::string pose_line(std::uint64_t frame, int id, const Eigen::Isometry3d& p, double error_px) {
  adapters::Json j;
  j["frame"] = frame;
  j["id"] = id;
  j["R"] = adapters::Json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) j["R"].push_back(p.linear()(r, c));
  j["t"] = {p.translation().x(), p.translation().y(), p.translation().z()};
  j["reprojection_error_px"] = error_px;
  return adapters::json_line(j);
}

// The poses of a JSON-lines file in pose_line's format, by (frame, id).
std::map<std::pair<std::uint64_t, int>, Eigen::Isometry3d> read_poses(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw adapters::ConfigError(path + ": cannot be read");
  std::map<std::pair<std::uint64_t, int>, Eigen::Isometry3d> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = path + ":" + std::to_string(n);
    const adapters::Json j = adapters::parse_json(line, where);
    const auto number = [&](const adapters::Json& v, const char* key) {
      if (!v.is_number()) throw adapters::ConfigError(where + ": '" + key + "' must hold numbers, not " + v.dump());
      return v.get<double>();
    };
    if (!j.is_object() || !j.contains("frame") || !j["frame"].is_number_unsigned() || !j.contains("id") ||
        !j["id"].is_number_integer() || !j.contains("R") || !j["R"].is_array() || j["R"].size() != 9 ||
        !j.contains("t") || !j["t"].is_array() || j["t"].size() != 3)
      throw adapters::ConfigError(where +
                                  ": expected {\"frame\": i, \"id\": n, \"R\": [9 numbers], \"t\": [3 numbers], ...}");
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    for (int k = 0; k < 9; ++k) p.linear()(k / 3, k % 3) = number(j["R"][k], "R");
    for (int k = 0; k < 3; ++k) p.translation()(k) = number(j["t"][k], "t");
    out[{j["frame"].get<std::uint64_t>(), j["id"].get<int>()}] = p;
  }
  return out;
}

std::pair<int, int> parse_resolution(const std::string& s) {
  int w = 0, h = 0;
  char x = 0;
  if (std::sscanf(s.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 || w > 8192 || h > 8192)
    throw std::invalid_argument("--resolution must be WIDTHxHEIGHT, e.g. 640x480, not '" + s + "'");
  return {w, h};
}

struct TrackOptions {
  std::string source, camera, out, truth;
  TrackerParams tracker;
};

int track(const TrackOptions& o) {
  const TrackerParams& p = o.tracker;
  check(p);
  const std::string& camera_file = o.camera;
  Intrinsics k = adapters::vision::read_intrinsics(camera_file);
  const auto truth = o.truth.empty() ? decltype(read_poses("")){} : read_poses(o.truth);
  std::unique_ptr<adapters::vision::Source> source = adapters::vision::open_path(o.source);
  const std::string& out_path = o.out;
  std::ofstream out(out_path);
  if (!out) throw std::runtime_error(out_path + ": cannot be written");
  std::cerr << "track: " << source->describe() << std::endl;

  std::unique_ptr<Tracker> tracker;
  std::uint64_t frames = 0, with_tag = 0, detections = 0, misses = 0, unreadable = 0, wrong_size = 0;
  runtime::Window trans(kMaxFrames), rot(kMaxFrames), ms(kMaxFrames);
  std::int64_t last_progress = runtime::mono_ns();
  for (adapters::vision::Frame f; source->next(f);) {
    ++frames;
    if (!f.problem.empty()) {
      std::cerr << "track: frame " << f.index << ": " << f.problem << ", skipped" << std::endl;
      ++unreadable;
      continue;
    }
    if (!tracker) {
      k = adapters::vision::with_frame_size(k, f.image.cols, f.image.rows, camera_file);
      tracker = std::make_unique<Tracker>(p, k);
    }
    if (f.image.cols != k.width || f.image.rows != k.height) {
      std::cerr << "track: frame " << f.index << " is " << f.image.cols << "x" << f.image.rows << ", not the "
                << k.width << "x" << k.height << " of " << camera_file << ", skipped" << std::endl;
      ++wrong_size;
      continue;
    }
    const std::int64_t t0 = runtime::mono_ns();
    const std::vector<Observation> seen = tracker->track(f.image);
    ms.add((runtime::mono_ns() - t0) * 1e-6);
    if (seen.empty() && ++misses <= kNamedMisses)
      std::cerr << "track: frame " << f.index << ": no " << p.detector.family << " tag found" << std::endl;
    with_tag += !seen.empty();
    for (const Observation& tag : seen) {
      ++detections;
      out << pose_line(f.index, tag.detection.id, tag.pose.tag_in_camera, tag.pose.reprojection_error_px) << '\n';
      const auto t = truth.find({f.index, tag.detection.id});
      if (t == truth.end()) continue;
      trans.add(100 * (tag.pose.tag_in_camera.translation() - t->second.translation()).norm() /
                t->second.translation().norm());
      rot.add(angle_between(tag.pose.tag_in_camera.linear(), t->second.linear()) * 180 / M_PI);
    }
    if (runtime::mono_ns() - last_progress > 2'000'000'000) {
      last_progress = runtime::mono_ns();
      std::cerr << "track: " << frames << " frames, " << with_tag << " with a tag" << std::endl;
    }
  }
  out.close();
  if (!out) throw std::runtime_error(out_path + ": write failed");
  if (misses > kNamedMisses) std::cerr << "track: ... and " << misses - kNamedMisses << " more frames without a tag\n";
  std::printf(
      "track: %llu frames, %llu with a tag, %llu detections written to %s; %llu unreadable, %llu of another "
      "size, %llu tags no pose fits; detection and pose median %.2f ms a frame\n",
      (unsigned long long)frames, (unsigned long long)with_tag, (unsigned long long)detections, out_path.c_str(),
      (unsigned long long)unreadable, (unsigned long long)wrong_size,
      (unsigned long long)(tracker ? tracker->unposed() : 0), ms.percentile(0.5));
  if (!truth.empty())
    std::printf(
        "track: against %s: %zu of %zu true poses detected; translation error p50 %.3f%% p95 %.3f%% of "
        "distance, rotation error p50 %.3f deg p95 %.3f deg\n",
        o.truth.c_str(), trans.size(), truth.size(), trans.percentile(0.5), trans.percentile(0.95), rot.percentile(0.5),
        rot.percentile(0.95));
  if (detections == 0) {
    std::cerr << "track: no tag in any frame: is the family (" << p.detector.family
              << ") right, and the tag whole and in focus?" << std::endl;
    return 1;
  }
  return 0;
}

struct SynthOptions {
  std::string out, resolution = "640x480", condition = "clean";
  int frames = 60;
  double rate = 30;
  Marker marker;
  bool video = false;
};

int synth(const SynthOptions& o) {
  const auto [w, h] = parse_resolution(o.resolution);
  const int n = o.frames;
  const double rate = o.rate;
  const Marker& m = o.marker;
  const Intrinsics k = synthetic_intrinsics(w, h);
  adapters::vision::SyntheticSource source(SyntheticCamera(k, m), condition(o.condition), rate, std::uint64_t(n));
  const fs::path dir = o.out;
  fs::create_directories(dir / "frames");
  adapters::vision::write_intrinsics((dir / "camera.yaml").string(), k);
  std::ofstream truth(dir / "truth.jsonl");
  if (!truth) throw std::runtime_error((dir / "truth.jsonl").string() + ": cannot be written");
  cv::VideoWriter video;
  if (o.video) {
    // Motion JPEG: OpenCV encodes it itself, whatever codecs the system has.
    video.open((dir / "video.avi").string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), rate, cv::Size(w, h), false);
    if (!video.isOpened()) throw std::runtime_error((dir / "video.avi").string() + ": cannot be written");
    video.set(cv::VIDEOWRITER_PROP_QUALITY, 95);
  }
  std::cerr << "synth: " << source.describe() << std::endl;
  for (adapters::vision::Frame f; source.next(f);) {
    const fs::path file = dir / "frames" / cv::format("frame_%06llu.png", (unsigned long long)f.index);
    if (!cv::imwrite(file.string(), f.image)) throw std::runtime_error(file.string() + ": cannot be written");
    if (video.isOpened()) video.write(f.image);
    truth << pose_line(f.index, m.id, source.truth(f.index), 0) << '\n';
  }
  truth.close();
  if (!truth) throw std::runtime_error((dir / "truth.jsonl").string() + ": write failed");
  std::printf(
      "synth: wrote %s/frames/ (%d PNG frames)%s, camera.yaml and truth.jsonl (the true poses, in hcosim "
      "track's format)\n",
      dir.c_str(), int(n), video.isOpened() ? ", video.avi (MJPG)" : "");
  std::printf(
      "try: hcosim track --source %s/frames --camera %s/camera.yaml --tag-size %g --out poses.jsonl --truth "
      "%s/truth.jsonl\n",
      dir.c_str(), dir.c_str(), m.tag_size, dir.c_str());
  return 0;
}

int video(const std::string& path) {
  if (!fs::is_regular_file(path)) throw std::runtime_error(path + ": no such file");
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);
  if (!cap.isOpened()) cap.open(path);
  if (!cap.isOpened()) throw std::runtime_error(path + ": OpenCV cannot read it as a video");
  // A frame is blank when it is one flat colour: grey levels' standard
  // deviation under 2 (an encoder's noise on a uniform frame stays below).
  constexpr double kFlat = 2;
  std::uint64_t frames = 0, blank = 0;
  cv::Mat f, grey;
  cv::Scalar mean, sd;
  while (cap.read(f) && !f.empty()) {
    ++frames;
    if (f.channels() == 3)
      cv::cvtColor(f, grey, cv::COLOR_BGR2GRAY);
    else
      grey = f;
    cv::meanStdDev(grey, mean, sd);
    blank += sd[0] < kFlat;
  }
  std::printf("%s: %llu frames, %dx%d at %.3g fps, %llu blank, %llu not blank\n", path.c_str(),
              (unsigned long long)frames, int(cap.get(cv::CAP_PROP_FRAME_WIDTH)),
              int(cap.get(cv::CAP_PROP_FRAME_HEIGHT)), cap.get(cv::CAP_PROP_FPS), (unsigned long long)blank,
              (unsigned long long)(frames - blank));
  return frames ? 0 : 1;
}

}  // namespace

void add_track(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<TrackOptions>();
  DetectorParams& d = o->tracker.detector;
  CLI::App* c = app.add_subcommand("track",
                                   "detect AprilTags in a video or an image folder, one JSON line per detection; with "
                                   "--truth, the errors against known poses");
  c->add_option("--source", o->source, "a video file or a folder of images")
      ->option_text("VIDEO_OR_FOLDER")
      ->required();
  c->add_option("--camera", o->camera, "the camera's intrinsics (OpenCV YAML; docs/tracking.md)")
      ->option_text("INTRINSICS.yaml")
      ->required();
  c->add_option("--tag-size", o->tracker.tag_size, "the tag's black square side, m")
      ->option_text("M")
      ->required()
      ->check(runtime::within(adapters::tag::kMinSize, adapters::tag::kMaxSize));
  c->add_option("--out", o->out, "the poses to write, JSON lines")->option_text("POSES.jsonl")->required();
  c->add_option("--truth", o->truth, "known poses to measure the errors against (synth's truth.jsonl)")
      ->option_text("TRUTH.jsonl");
  c->add_option("--family", d.family, "tag family (default " + d.family + ")")
      ->option_text("F")
      ->check(CLI::IsMember(adapters::tag::kFamilies).description(""));
  c->add_option("--decimate", d.quad_decimate, "detect on an image this many times smaller (default 1.5)")
      ->option_text("D")
      ->check(runtime::within(1, 16));
  c->add_option("--sigma", d.quad_sigma, "Gaussian blur before detection, px (default 0)")
      ->option_text("S")
      ->check(runtime::within(0, 100));
  c->add_option("--threads", d.nthreads, "detector threads (default 1)")->option_text("N")->check(CLI::Range(1, 64));
  c->callback([&chosen, o] { chosen = [o] { return track(*o); }; });
}

void add_synth(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<SynthOptions>();
  CLI::App* c = app.add_subcommand("synth", "write a synthetic marker sequence (PNG frames, camera.yaml, truth.jsonl)");
  c->add_option("--out", o->out, "the folder to write")->option_text("DIR")->required();
  c->add_option("--frames", o->frames, "frames (default 60)")->option_text("N")->check(CLI::Range(1, 100000));
  c->add_option("--rate", o->rate, "frame rate, Hz (default 30)")->option_text("HZ")->check(runtime::within(0.1, 1000));
  c->add_option("--resolution", o->resolution, "image size (default 640x480)")->option_text("WxH");
  c->add_option("--condition", o->condition, "image condition (default clean)")
      ->option_text("C")
      ->check(CLI::IsMember({"clean", "noisy", "blurred"}).description(""));
  c->add_option("--family", o->marker.family, "tag family (default " + o->marker.family + ")")
      ->option_text("F")
      ->check(CLI::IsMember(adapters::tag::kFamilies).description(""));
  c->add_option("--tag-id", o->marker.id, "tag id (default 0)")
      ->option_text("ID")
      ->check(CLI::Range(0, adapters::tag::kMaxId));
  c->add_option("--tag-size", o->marker.tag_size, "tag size, m (default 0.05)")
      ->option_text("M")
      ->check(runtime::within(adapters::tag::kMinSize, adapters::tag::kMaxSize));
  c->add_flag("--video", o->video, "also write video.avi (Motion JPEG)");
  c->callback([&chosen, o] { chosen = [o] { return synth(*o); }; });
}

void add_video(CLI::App& app, Command& chosen) {
  auto path = std::make_shared<std::string>();
  CLI::App* c = app.add_subcommand("video", "count a video's frames, and those that are blank (one flat colour)");
  c->add_option("FILE", *path, "the video")->required();
  c->callback([&chosen, path] { chosen = [path] { return video(*path); }; });
}

}  // namespace hcosim::services::cli
