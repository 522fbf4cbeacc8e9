// bench contact: what the hand feels from each object kind, through the
// real services. For each kind a lockstep deployment (`hcosim up`, its
// recording) runs the simulated Omni's virtual user against a scene of
// that kind's objects in hcosim_rigid or hcosim_deformable at 1 kHz; the
// recorded HapticState and ForceFeedback give, per object:
//
// stroke: a 3 mm press held, then slid 20 mm at 1 cm/s across a face:
//   the largest ratio of tangential to normal force while sliding (the
//   stroke's second half), and its excess over the object's friction;
//   normal and tangential to the contact normal a deformable object's
//   answer reports (the touched surface's, which a membrane tilts as its
//   dent is dragged), or to a rigid body's face (the rigid service
//   reports its coupling's direction there, friction's lean included);
//   and the share of the stroke's ticks in contact (a stylus that falls
//   through a membrane feels nothing).
// entry: a frictionless twin pressed between its nodes: the largest angle
//   between the felt force and the face's rest normal (kinds without a
//   friction key are pressed themselves).
// Forces under a quarter of the phase's typical one (its median, for the
// stroke; its largest, for the entry) are the contact's edge, not its
// direction, and are left out.
// onset: the first tick of contact of the measured press: the force over
//   the contact's stiffness (the answer's own) times that tick's motion.
// hold: the force's spread (standard deviation over mean) over the last
//   0.5 s of a 1 s hold; for the default scene's liver on its four times
//   stiffer lobe.
// push: a rigid cube pushed 4 cm along the marker at 5 cm/s: the mean
//   felt force over the middle half of the push, over the floor's
//   friction times the cube's weight.
//
// The script marks its phases with stylus buttons no service reads (bits
// 1 to 3 of the Omni's four), so that the samples of each are found by
// their state.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <thread>

#include <Eigen/Core>

#include "services/bench/bench.h"
#include "services/bench/harness.h"
#include "services/recording/recording.h"

namespace hcosim::services::bench {
namespace {

namespace fs = std::filesystem;

// Phase marks: HapticState.buttons & kPhase (bit 0 grabs a hybrid object).
constexpr unsigned kPhase = 14, kEntry = 2, kHold = 4, kStroke = 8, kPush = 6;

struct Kind {
  std::string name;      // the suite's `kind` param
  std::string service;   // rigid or deformable
  std::string objects;   // the scene's objects, YAML list items
  std::string script;    // the virtual user's actions
  std::string target;    // pressed, held and stroked
  std::string twin;      // pressed between its nodes, frictionless ("" none)
  std::string pushed;    // pushed along the plane ("" none)
  double mu = NAN;       // the target's friction (NaN: a kind without one)
  double push_need = 0;  // N: the pushed cube's floor friction times its weight
  double duration = 0;   // s simulated
  // The outward normal of the target's surface at a HIP.
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> normal;
};

Eigen::Vector3d up(const Eigen::Vector3d&) { return Eigen::Vector3d::UnitZ(); }

// The press-hold-stroke script at (x, y) above a face at height `top`,
// after the entry press at (ex, ey) above `entry_top`.
std::string stroke_script(double x, double y, double top, double ex, double ey, double entry_top) {
  std::ostringstream o;
  o << "start: [" << ex << ", " << ey << ", " << entry_top + 0.01 << "]\nactions:\n"
    << "  - move_to: {to: [" << ex << ", " << ey << ", " << entry_top + 0.001 << "], speed: 0.05}\n"
    << "  - press: {depth: 0.004, speed: 0.01, buttons: " << kEntry << "}\n"
    << "  - hold: {duration: 0.3, buttons: " << kEntry << "}\n"
    << "  - release: {speed: 0.02}\n"
    << "  - move_to: {to: [" << x << ", " << y << ", " << top + 0.01 << "], speed: 0.1}\n"
    << "  - move_to: {to: [" << x << ", " << y << ", " << top + 0.001 << "], speed: 0.05}\n"
    << "  - press: {depth: 0.004, speed: 0.01}\n"
    << "  - hold: {duration: 1.0, buttons: " << kHold << "}\n"
    << "  - stroke: {by: [0.02, 0, 0], speed: 0.01, buttons: " << kStroke << "}\n"
    << "  - release: {speed: 0.02}\n";
  return o.str();
}

std::vector<Kind> kinds() {
  std::vector<Kind> out;
  {
    Kind k;
    k.name = "hybrid_cube", k.service = "deformable";
    k.objects =
        "    - {name: cube, kind: deformable, model: hybrid, centre: [0, 0, 0.015], size: 0.03}\n"
        "    - {name: twin, kind: deformable, model: hybrid, centre: [0, 0.05, 0.015], size: 0.03, friction: 0}\n";
    k.script = stroke_script(-0.01, 0, 0.03, 0.0037, 0.0523, 0.03);
    k.target = "cube", k.twin = "twin", k.mu = 0.3, k.duration = 7, k.normal = up;
    out.push_back(k);
  }
  {
    // The default scene's liver, its +x lobe four times stiffer: pressed
    // from above on that lobe (its top 11.1 mm high there), held.
    Kind k;
    k.name = "organ_stiff_side", k.service = "deformable";
    k.objects = std::string("    - {name: organ, kind: deformable, model: hybrid, mesh: ") + HCOSIM_LIVER_OBJ +
                ",\n       centre: [0, 0, 0.0075], size: 0.045, elements: 16, stiff_ratio: 4}\n";
    k.script =
        "start: [0.012, 0, 0.02]\nactions:\n"
        "  - press: {depth: 0.0129, speed: 0.02}\n"
        "  - hold: {duration: 1.0, buttons: 4}\n"
        "  - release: {speed: 0.03}\n";
    k.target = "organ", k.duration = 3;
    k.normal = up;
    out.push_back(k);
  }
  {
    Kind k;
    k.name = "sheet", k.service = "deformable";
    k.objects =
        "    - {name: sheet, kind: deformable, model: sheet, centre: [0, 0, 0.02], size: 0.04}\n"
        "    - {name: twin, kind: deformable, model: sheet, centre: [0, 0.05, 0.02], size: 0.04, friction: 0}\n";
    k.script = stroke_script(-0.01, -0.005, 0.02, 0.0037, 0.0563, 0.02);
    k.target = "sheet", k.twin = "twin", k.mu = 0.3, k.duration = 7, k.normal = up;
    out.push_back(k);
  }
  {
    Kind k;
    k.name = "semisphere", k.service = "deformable";
    k.objects =
        "    - {name: dome, kind: deformable, model: semisphere, centre: [0, 0, 0], size: 0.02}\n"
        "    - {name: twin, kind: deformable, model: semisphere, centre: [0, 0.05, 0], size: 0.02, friction: 0}\n";
    // A short stroke over the top (the normal followed as the dome's).
    k.script = stroke_script(-0.01, 0, std::sqrt(0.02 * 0.02 - 0.01 * 0.01), 0.0023, 0.0531, 0.02);
    k.target = "dome", k.twin = "twin", k.mu = 0.3, k.duration = 7;
    // Either dome's outward normal at a HIP: from the nearer one's centre.
    k.normal = [](const Eigen::Vector3d& h) {
      return Eigen::Vector3d(h - Eigen::Vector3d(0, h.y() > 0.025 ? 0.05 : 0, 0)).normalized();
    };
    out.push_back(k);
  }
  {
    Kind k;
    k.name = "rigid_cube", k.service = "rigid";
    k.objects =
        "    - {name: box, kind: rigid, shape: cube, size: 0.012, mass: 0.05, centre: [0, 0, 0.012]}\n"
        "    - {name: twin, kind: rigid, shape: cube, size: 0.012, mass: 0.05, centre: [0, 0.05, 0.012], "
        "friction: 0}\n"
        "    - {name: pushed, kind: rigid, shape: cube, size: 0.012, mass: 0.05, centre: [0, -0.05, 0.012]}\n";
    std::string s = stroke_script(-0.01, 0, 0.024, 0.0037, 0.0523, 0.024);
    s += "  - move_to: {to: [-0.016, -0.05, 0.03], speed: 0.1}\n"
         "  - move_to: {to: [-0.016, -0.05, 0.012], speed: 0.05}\n"
         "  - move_to: {to: [0.024, -0.05, 0.012], speed: 0.05, buttons: 6}\n";
    k.script = s;
    k.target = "box", k.twin = "twin", k.pushed = "pushed", k.mu = 0.3, k.duration = 9, k.normal = up;
    k.push_need = 0.5 * 0.05 * 9.81;  // the default floor_friction
    out.push_back(k);
  }
  {
    // A resting sphere pressed on its top and held (stroked, it would roll).
    Kind k;
    k.name = "rigid_sphere", k.service = "rigid";
    k.objects = "    - {name: ball, kind: rigid, shape: sphere, size: 0.012, mass: 0.05, centre: [0, 0, 0.012]}\n";
    k.script =
        "start: [0, 0, 0.034]\nactions:\n"
        "  - move_to: {to: [0, 0, 0.025], speed: 0.05}\n"
        "  - press: {depth: 0.004, speed: 0.01}\n"
        "  - hold: {duration: 1.0, buttons: 4}\n"
        "  - release: {speed: 0.02}\n";
    k.target = "ball", k.duration = 2.5;
    k.normal = up;
    out.push_back(k);
  }
  return out;
}

// Runs `hcosim up` on the kind's deployment, recording, within a limit;
// false if it ran past it (and was stopped).
bool run_once(const Context& c, const Kind& k, const fs::path& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "user.yaml") << k.script;
  std::ofstream(dir / "deploy.yaml") << "domain: " << c.domain
                                     << "\nmode: lockstep\nstep: 0.001\nduration: " << k.duration
                                     << "\nscene:\n  objects:\n"
                                     << k.objects << "services:\n"
                                     << "  - {name: omni, kind: haptic, rate: 1000, params: {script: user.yaml}}\n"
                                     << "  - {name: " << k.service << ", kind: " << k.service
                                     << ", rate: 1000, params: {device: omni}}\n";
  const fs::path rec = dir / "run.rec", log = dir / "up.log";
  const pid_t pid = start_up(dir / "deploy.yaml", dir / "out", log, rec);
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(int(30 + 5 * k.duration));
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > limit) {
      kill(pid, SIGTERM);
      waitpid(pid, &status, 0);
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("contact: hcosim up failed for " + k.name + "; " + log.string());
  return true;
}

// The kind's recording, from a second run if the first stalled: a lockstep
// run recorded by hcosim up has been seen to stall at one step every 2 s
// ("outputs not acknowledged by every reader in 2 s"), in about one suite
// run in two on this machine; the stalled runs are counted in the row.
fs::path run(const Context& c, const Kind& k, int& stalled) {
  const fs::path dir = c.work / "contact_run" / k.name;
  for (int attempt = 0; attempt < 3; ++attempt) fs::remove_all(dir.string() + ".stalled" + std::to_string(attempt));
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (run_once(c, k, dir)) return dir / "run.rec";
    ++stalled;
    progress("contact: " + k.name + " stalled past its limit (" + (dir / "up.log").string() + "); again");
    // What each service said of it: its first unacknowledged step, and
    // how many (what a fix of the stall needs; the run's folder may not
    // outlive a test).
    if (fs::is_directory(dir / "out" / "logs"))
      for (const auto& log : fs::directory_iterator(dir / "out" / "logs")) {
        std::ifstream in(log.path());
        std::string line, first;
        int count = 0;
        while (std::getline(in, line))
          if (line.find("not acknowledged") != std::string::npos && count++ == 0) first = line;
        if (count > 0) progress("contact:   " + first + " (" + std::to_string(count) + " such steps)");
      }
    fs::rename(dir, dir.string() + ".stalled" + std::to_string(attempt));
  }
  throw std::runtime_error("contact: " + k.name + " stalled three times; " + dir.string() + ".stalled*");
}

struct Tick {
  Eigen::Vector3d hip = Eigen::Vector3d::Zero();
  unsigned buttons = 0;
  std::map<std::string, ForceFeedback> answers;  // by source
};

std::map<std::uint64_t, Tick> read(const fs::path& rec) {
  std::map<std::uint64_t, Tick> ticks;
  recording::RecordingReader in(rec.string());
  recording::Record r;
  while (in.next(r)) {
    if (r.topic == "HapticState") {
      const HapticState s = recording::from_cdr<HapticState>(r.cdr);
      Tick& t = ticks[s.seq()];
      t.hip = Eigen::Vector3d(s.position().x(), s.position().y(), s.position().z());
      t.buttons = s.buttons();
    } else if (r.topic == "ForceFeedback") {
      const ForceFeedback f = recording::from_cdr<ForceFeedback>(r.cdr);
      ticks[f.answers_seq()].answers[f.source().to_string()] = f;
    }
  }
  return ticks;
}

Eigen::Vector3d force(const ForceFeedback& f) { return Eigen::Vector3d(f.force().x(), f.force().y(), f.force().z()); }

Row measure(const Kind& k, const std::map<std::uint64_t, Tick>& ticks) {
  Row row{"contact", {{"kind", k.name}, {"object", k.target}}, {}};
  const auto answer = [](const Tick& t, const std::string& source) -> const ForceFeedback* {
    const auto it = t.answers.find(source);
    return it == t.answers.end() || !it->second.in_contact() ? nullptr : &it->second;
  };
  // Onset: the target's first tick in contact.
  const Tick* last = nullptr;
  for (const auto& [seq, t] : ticks) {
    const ForceFeedback* f = answer(t, k.target);
    if (f && last) {
      const double motion = (t.hip - last->hip).norm(), k_contact = f->stiffness_n_per_m();
      row.metrics.push_back({"onset_force_n", force(*f).norm()});
      row.metrics.push_back({"onset_ratio", k_contact * motion > 0 ? force(*f).norm() / (k_contact * motion) : NAN});
      break;
    }
    last = &t;
  }
  // Hold: the last 0.5 s of the hold.
  std::vector<double> hold;
  for (const auto& [seq, t] : ticks)
    if ((t.buttons & kPhase) == kHold)
      if (const ForceFeedback* f = answer(t, k.target)) hold.push_back(force(*f).norm());
  if (hold.size() > 500) {
    hold.erase(hold.begin(), hold.end() - 500);
    double sum = 0, squares = 0;
    for (const double f : hold) sum += f, squares += f * f;
    const double mean = sum / double(hold.size());
    row.metrics.push_back({"hold_mean_n", mean});
    row.metrics.push_back({"hold_min_n", *std::min_element(hold.begin(), hold.end())});
    row.metrics.push_back({"hold_max_n", *std::max_element(hold.begin(), hold.end())});
    row.metrics.push_back(
        {"hold_spread_pct", 100 * std::sqrt(std::max(0.0, squares / double(hold.size()) - mean * mean)) / mean});
  }
  // Stroke: tangential over normal in the stroke's second half.
  std::vector<std::pair<double, double>> stroke;  // (ratio, normal)
  int stroke_ticks = 0;
  for (const auto& [seq, t] : ticks)
    if ((t.buttons & kPhase) == kStroke && ++stroke_ticks)
      if (const ForceFeedback* f = answer(t, k.target)) {
        const Eigen::Vector3d reported(f->normal().x(), f->normal().y(), f->normal().z());
        const Eigen::Vector3d n =
            k.service == "deformable" && reported.norm() > 0.5 ? reported.normalized() : k.normal(t.hip);
        const Eigen::Vector3d F = force(*f);
        stroke.push_back({(F - F.dot(n) * n).norm() / std::max(F.dot(n), 1e-12), F.dot(n)});
      }
  if (stroke_ticks > 100)
    row.metrics.push_back({"stroke_in_contact_pct", 100.0 * double(stroke.size()) / stroke_ticks});
  if (stroke.size() > 100) {
    std::vector<double> normals;
    for (std::size_t i = stroke.size() / 2; i < stroke.size(); ++i) normals.push_back(stroke[i].second);
    std::nth_element(normals.begin(), normals.begin() + normals.size() / 2, normals.end());
    const double edge = 0.25 * normals[normals.size() / 2];
    double most = 0, sum = 0;
    int n = 0;
    for (std::size_t i = stroke.size() / 2; i < stroke.size(); ++i)
      if (stroke[i].second > edge) most = std::max(most, stroke[i].first), sum += stroke[i].first, ++n;
    row.metrics.push_back({"stroke_ratio_max", most});
    row.metrics.push_back({"stroke_ratio_mean", n ? sum / n : NAN});
    if (!std::isnan(k.mu)) {
      row.metrics.push_back({"friction", k.mu});
      row.metrics.push_back({"stroke_excess", most - k.mu});
    }
  }
  // Entry: the frictionless twin (or the target) pressed between nodes.
  const std::string entered = k.twin.empty() ? k.target : k.twin;
  double worst = -1, largest = 0;
  for (const auto& [seq, t] : ticks)
    if ((t.buttons & kPhase) == kEntry)
      if (const ForceFeedback* f = answer(t, entered)) largest = std::max(largest, force(*f).norm());
  for (const auto& [seq, t] : ticks)
    if ((t.buttons & kPhase) == kEntry)
      if (const ForceFeedback* f = answer(t, entered)) {
        const Eigen::Vector3d F = force(*f);
        if (F.norm() <= 0.25 * largest) continue;
        const double c = std::clamp(F.normalized().dot(k.normal(t.hip)), -1.0, 1.0);
        worst = std::max(worst, std::acos(c) * 180 / M_PI);
      }
  if (worst >= 0) row.metrics.push_back({"entry_angle_deg", worst});
  // Push: the middle half of the push's ticks in contact.
  std::vector<double> push;
  for (const auto& [seq, t] : ticks)
    if ((t.buttons & kPhase) == kPush)
      if (const ForceFeedback* f = answer(t, k.pushed)) push.push_back(force(*f).norm());
  if (push.size() > 100) {
    double sum = 0;
    for (std::size_t i = push.size() / 4; i < 3 * push.size() / 4; ++i) sum += push[i];
    const double mean = sum / double(3 * push.size() / 4 - push.size() / 4);
    row.metrics.push_back({"push_mean_n", mean});
    row.metrics.push_back({"push_need_n", k.push_need});
    row.metrics.push_back({"push_ratio", mean / k.push_need});
  }
  return row;
}

std::vector<Row> contact_rows(const Context& c) {
  std::vector<Row> rows;
  for (const Kind& k : kinds()) {
    progress("contact: " + k.name + " in " + k.service + ", " + text(k.duration) + " s in lockstep");
    int stalled = 0;
    Row row = measure(k, read(run(c, k, stalled)));
    row.metrics.push_back({"stalled_runs", double(stalled)});
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

Suite contact_suite() {
  Suite s{"contact",
          "what the hand feels from each object kind through the real services (lockstep, the simulated Omni's "
          "virtual user): friction while sliding, the force's direction entering between nodes, onset, a steady "
          "hold, a pushed cube",
          contact_rows};
  s.tables = {{"contact",
               "One lockstep run per kind (hcosim up, recorded): `stroke_ratio_max` is the largest tangential over "
               "normal force (to the touched surface's normal a deformable object reports, a rigid face's) in a 20 mm "
               "stroke's second half at 1 cm/s "
               "under a 3 mm press, against `friction` (`stroke_in_contact_pct`: the share of its ticks in contact); "
               "`entry_angle_deg` the largest angle from the face's normal pressing a frictionless twin between its "
               "nodes (the object itself for kinds without a friction key); `onset_ratio` the first contact tick's "
               "force over the answer's stiffness times that tick's motion; `hold_spread_pct` the force's standard "
               "deviation over its mean in the last 0.5 s of a 1 s hold (`hold_min_n`, `hold_max_n` its range); "
               "`push_ratio` a 50 g cube's mean felt force "
               "pushed at 5 cm/s over floor friction times its weight."}};
  s.goals = {
      {"tangential over normal while sliding at most the friction + 0.02", "contact", "stroke_excess", 0.02},
      {"a stroke stays in contact (at least 99 % of its ticks)", "contact", "stroke_in_contact_pct", 99, "", "", true},
      {"entering between nodes within 5 degrees of the normal", "contact", "entry_angle_deg", 5},
      {"no onset jump above stiffness x motion", "contact", "onset_ratio", 1},
      {"hold spread under 2 %", "contact", "hold_spread_pct", 2},
      {"a pushed cube's force within 20 % of friction x weight (above)", "contact", "push_ratio", 1.2},
      {"a pushed cube's force within 20 % of friction x weight (below)", "contact", "push_ratio", 0.8, "", "", true}};
  return s;
}

}  // namespace hcosim::services::bench
