// hcosim bench: the suites and the report rows they produce.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "services/runtime/args.h"
#include "services/runtime/stats.h"

namespace hcosim::services::bench {

using Value = std::variant<double, std::string>;

// One measured configuration. Metric names carry their unit (p99_us,
// ms_per_sim_s, rel_error, ...).
struct Row {
  std::string name;
  std::vector<std::pair<std::string, Value>> params;
  std::vector<std::pair<std::string, double>> metrics;
};

// A param's value as the report prints it: numbers to 4 significant
// digits, integers whole.
std::string text(const Value& v);
std::string text(double v);

struct Context {
  bool quick = false;
  int domain = 0;
  std::filesystem::path out;   // where the report (and any plot) goes
  std::filesystem::path work;  // where the suites run their processes and keep their logs, out of the report's way
};

// How index.md shows the rows of one name: a caption saying what was
// measured, on what, and against what.
struct Table {
  std::string row, caption;
};

// A scatter plot of two metrics of the rows of one name (time against error
// where the suite has an error): one series per value of the `series`
// params, one plot per value of the `group` params.
struct Plot {
  std::string row;
  std::string x, y;              // metric names, or numeric params
  std::string x_label, y_label;  // with units
  std::vector<std::string> series = {}, group = {};
  std::pair<std::string, std::string> baseline = {};  // param and value of the peer's rows, drawn grey
  bool log_x = true, log_y = true;
};

// A stated goal: `metric` is at most `bound` (at least, with `at_least`)
// in every row named `row` (whose param `where` has the value `is`, when
// `where` is given).
struct Goal {
  std::string text;
  std::string row, metric;
  double bound;
  std::string where = "", is = "";
  bool at_least = false;
};

struct Suite {
  const char* name;
  const char* what;
  std::function<std::vector<Row>(const Context&)> run;
  std::vector<Table> tables = {};  // rows of a name without one get a table captioned by its name
  std::vector<Plot> plots = {};
  std::vector<Goal> goals = {};
};

inline void progress(const std::string& line) { std::cerr << "bench: " << line << std::endl; }

// The median of v: the mean of its middle two for an even count, NaN for none.
double median(std::vector<double> v);

// `hcosim bench SUITE|all|list|report ...`: runs suites and writes their
// report (bench.cc).
void add_bench(CLI::App& app, runtime::Command& chosen);

// `hcosim bench-peer ...`, hidden: the far end of the suites' round
// trips and the dds suite's mesh readers (peer.cc).
void add_peer(CLI::App& app, runtime::Command& chosen);

// Mass-spring integrators and MuJoCo on the same lattices: massspring.cc.
Suite massspring_suite();

// The haptic device's closed loop, the stiff-wall rig: haptic.cc.
Suite haptic_suite();

// The hybrid deformable model's parts and pipeline: hybrid.cc.
Suite hybrid_suite();

// The rigid model against eq 2 and MuJoCo, and its step cost: rigid.cc.
Suite rigid_suite();

// Marker detection and pose against ground truth and ArUco: tracking.cc.
Suite tracking_suite();

// The AR view's frame against OpenCV drawing the same triangles: arview.cc.
Suite arview_suite();

// The default deployment for half an hour: soak.cc.
Suite soak_suite();

// What the hand feels from each object kind through the services: contact.cc.
Suite contact_suite();

// The live Foxglove bridge's cost at the default scene: foxglove.cc.
Suite foxglove_suite();

// The DDS transport: haptic round trips and mesh publishing against bare
// Fast DDS: dds.cc.
Suite dds_suite();

// Where a suite's plots go: DIR/SUITE_GROUP.png, one per group of each plot.
struct Figure {
  std::string row;
  std::filesystem::path file;
  std::string caption;
};

// Draws every plot of `s` from its rows into `dir` (report.cc).
std::vector<Figure> draw_plots(const Suite& s, const std::vector<Row>& rows, const std::filesystem::path& dir);

using Machine = std::vector<std::pair<std::string, std::string>>;

// The machine, compiler and libraries now, as (name, value) pairs.
Machine machine();

// The source tree a run measured: its commit, and whether the tree had
// changes git had not committed (untracked files count; ignored ones, such
// as build/, do not), asked of git when the run began.
struct Provenance {
  std::string commit = "unknown";  // git's full hash
  bool clean = false;
};
Provenance provenance();

// One suite's outcome, for the report.
struct Result {
  const Suite* suite;
  std::vector<Row> rows;
  std::vector<Figure> figures;
  std::string command;  // what measured it
  Machine machine;      // where and when
  Provenance tree;      // what it measured
  double seconds;       // wall time the suite took; NaN if not known
  std::string error;    // why the suite stopped, if it did
};

// Writes DIR/index.md: per suite its goals, tables and plots, and the
// machine (report.cc). `redrawn_by` names the command when the
// report is drawn again from the JSON files of an earlier run.
void write_index(const std::filesystem::path& dir, const std::vector<Result>& results,
                 const std::string& redrawn_by = "");

// The part of a page (docs/PERFORMANCE.md) drawn from a run's results:
// what measured them, on which tree, and every goal of every suite with
// its verdict and worst figure (report.cc). It stands in the page between
// kPageBegin and kPageEnd, lines of their own.
std::string page_part(const std::vector<Result>& results);
inline constexpr const char* kPageBegin =
    "<!-- Drawn by `hcosim bench report --out docs/bench --page docs/PERFORMANCE.md` from docs/bench/*.json: do not "
    "edit -->";
inline constexpr const char* kPageEnd = "<!-- End of the drawn part -->";

}  // namespace hcosim::services::bench
