// bench's report: the machine, each suite's plots, and DIR/index.md, all
// from measured rows; nothing in it is typed by hand but the suites'
// captions.
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include <fastrtps/config.h>
#include <mujoco/mujoco.h>
#include <Eigen/Core>
#include <opencv2/core/version.hpp>

#include "adapters/vision/media.h"
#include "services/bench/bench.h"
#include "services/report/plot.h"

namespace fs = std::filesystem;

namespace hcosim::services::bench {

std::string text(double v) {
  if (std::isfinite(v) && std::abs(v) < 1e15 && v == std::round(v)) return std::to_string(std::int64_t(v));
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

std::string text(const Value& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, double>)
          return text(x);
        else
          return x;
      },
      v);
}

namespace {

std::string first_line_with(const char* path, const std::string& prefix) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) {
      const auto colon = line.find(':');
      return colon == std::string::npos ? line : line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  return "";
}

const Value* param(const Row& r, const std::string& name) {
  for (const auto& [k, v] : r.params)
    if (k == name) return &v;
  return nullptr;
}

const double* metric(const Row& r, const std::string& name) {
  for (const auto& [k, v] : r.metrics)
    if (k == name) return &v;
  return nullptr;
}

// A metric, or else a numeric param, of that name.
std::optional<double> number(const Row& r, const std::string& name) {
  if (const double* m = metric(r, name)) return *m;
  if (const Value* v = param(r, name))
    if (const double* d = std::get_if<double>(v)) return *d;
  return std::nullopt;
}

// "mujoco Euler", "bare subscribers=3": strings as they are, numbers named,
// zeros (an option left off) omitted.
std::string label(const Row& r, const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) {
    const Value* v = param(r, n);
    if (!v) continue;
    std::string part;
    if (const double* d = std::get_if<double>(v)) {
      if (*d == 0) continue;
      part = n + "=" + text(*d);
    } else {
      part = std::get<std::string>(*v);
    }
    out += (out.empty() ? "" : " ") + part;
  }
  return out;
}

std::string file_safe(std::string s) {
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '.' && ch != '-') ch = '_';
  return s;
}

std::string md_cell(std::string s) {
  for (std::size_t i = s.find('|'); i != std::string::npos; i = s.find('|', i + 2)) s.replace(i, 1, "\\|");
  return s;
}

}  // namespace

Machine machine() {
  utsname u{};
  uname(&u);
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return {{"date", date},
          {"host", host},
          {"cpu", first_line_with("/proc/cpuinfo", "model name")},
          {"cores", std::to_string(std::thread::hardware_concurrency())},
          {"memory", first_line_with("/proc/meminfo", "MemTotal")},
          {"kernel", std::string(u.sysname) + " " + u.release},
          {"compiler", __VERSION__},
          {"fastdds", FASTRTPS_VERSION_STR},
          {"mujoco", mj_versionString()},
          {"opencv", CV_VERSION},
          {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                        std::to_string(EIGEN_MINOR_VERSION)}};
}

std::vector<Figure> draw_plots(const Suite& s, const std::vector<Row>& rows, const fs::path& dir) {
  std::vector<Figure> out;
  for (const Plot& p : s.plots) {
    // group -> series label -> points
    std::map<std::string, std::map<std::string, report::Series>> groups;
    for (const Row& r : rows) {
      const std::optional<double> x = number(r, p.x), y = number(r, p.y);
      if (r.name != p.row || !x || !y) continue;
      report::Series& series = groups[label(r, p.group)][label(r, p.series)];
      series.label = label(r, p.series);
      const Value* b = param(r, p.baseline.first);
      series.baseline = b && text(*b) == p.baseline.second;
      series.x.push_back(*x);
      series.y.push_back(*y);
    }
    for (const auto& [group, by_label] : groups) {
      std::vector<report::Series> series;
      for (const auto& [name, points] : by_label) series.push_back(points);
      const std::string stem = std::string(s.name) + "_" + p.row + "_" + (group.empty() ? p.y : file_safe(group));
      const fs::path file = dir / (stem + ".png");
      // The axes name the quantities; the title only says which rows.
      const std::string title = std::string(s.name) + " " + p.row + (group.empty() ? "" : ", " + group);
      adapters::vision::write_image(file.string(),
                                    report::plot_scatter(title, p.x_label, p.y_label, series, {p.log_x, p.log_y}));
      std::cout << "wrote " << file.string() << "\n";
      out.push_back({p.row, file, title + ": " + p.y_label + " against " + p.x_label});
    }
  }
  return out;
}

namespace {

void table(std::ostream& md, const std::vector<const Row*>& rows) {
  std::vector<std::string> params, metrics;
  const auto add = [](std::vector<std::string>& names, const std::string& n) {
    if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  };
  for (const Row* r : rows) {
    for (const auto& [k, v] : r->params) add(params, k);
    for (const auto& [k, v] : r->metrics) add(metrics, k);
  }
  md << "|";
  for (const auto& n : params) md << " " << n << " |";
  for (const auto& n : metrics) md << " **" << n << "** |";
  md << "\n|";
  for (std::size_t k = 0; k < params.size(); ++k) md << "---|";
  for (std::size_t k = 0; k < metrics.size(); ++k) md << "--:|";
  md << "\n";
  for (const Row* r : rows) {
    md << "|";
    for (const auto& n : params) {
      const Value* v = param(*r, n);
      md << " " << (v ? md_cell(text(*v)) : "") << " |";
    }
    for (const auto& n : metrics) {
      const double* v = metric(*r, n);
      md << " " << (v ? text(*v) : "") << " |";
    }
    md << "\n";
  }
  md << "\n";
}

// How the rows fare against a goal.
struct Verdict {
  int rows = 0;
  double worst = NAN;
  std::vector<std::string> misses;  // "value (params)" of each row over the bound
  bool met() const { return rows > 0 && misses.empty(); }
};

Verdict judge(const Goal& g, const std::vector<Row>& rows) {
  Verdict out;
  for (const Row& r : rows) {
    const double* v = metric(r, g.metric);
    const Value* w = g.where.empty() ? nullptr : param(r, g.where);
    if (r.name != g.row || !v || (!g.where.empty() && (!w || text(*w) != g.is))) continue;
    // The worst so far; a NaN, once seen, stays the worst.
    const bool first = out.rows++ == 0;
    if (first || (!std::isnan(out.worst) && (std::isnan(*v) || (g.at_least ? *v < out.worst : *v > out.worst))))
      out.worst = *v;
    if (!(g.at_least ? *v >= g.bound : *v <= g.bound)) {
      std::string where;
      for (const auto& [k, pv] : r.params) where += (where.empty() ? "" : ", ") + k + " " + text(pv);
      out.misses.push_back(text(*v) + " (" + where + ")");
    }
  }
  return out;
}

void goal(std::ostream& md, const Goal& g, const std::vector<Row>& rows) {
  const Verdict v = judge(g, rows);
  md << "- Goal: " << g.text << " (`" << g.metric << "` at " << (g.at_least ? "least " : "most ") << text(g.bound)
     << " in every `" << g.row << "` row" << (g.where.empty() ? "" : " with " + g.where + " " + g.is) << "): ";
  if (v.rows == 0) {
    md << "**not measured** (no such row)\n";
    return;
  }
  md << (v.met() ? "**met**" : "**not met**") << ", worst " << text(v.worst) << " over " << v.rows
     << (v.rows == 1 ? " row" : " rows");
  if (!v.met()) {
    md << "; missed by";
    for (const auto& m : v.misses) md << " " << m << ";";
  }
  md << "\n";
}

}  // namespace

namespace {

// "at commit H (a clean tree)" for each tree the results measured, with
// the suites that measured it when there is more than one.
std::string trees(const std::vector<Result>& results) {
  std::vector<std::pair<std::string, std::vector<std::string>>> by;  // "H, clean" -> suites
  for (const Result& r : results) {
    const std::string t = "commit `" + r.tree.commit + "` (" +
                          (r.tree.clean ? "a clean tree" : "**with changes git had not committed**") + ")";
    auto it = std::find_if(by.begin(), by.end(), [&](const auto& b) { return b.first == t; });
    if (it == by.end()) by.push_back({t, {}}), it = by.end() - 1;
    it->second.push_back(r.suite->name);
  }
  std::string out;
  for (const auto& [t, suites] : by) {
    out += (out.empty() ? "" : "; ") + std::string("at ") + t;
    if (by.size() > 1) {
      out += " for";
      for (const std::string& s : suites) out += " `" + s + "`";
    }
  }
  return out;
}

}  // namespace

std::string page_part(const std::vector<Result>& results) {
  std::ostringstream md;
  std::vector<std::string> commands;
  for (const Result& r : results)
    if (std::find(commands.begin(), commands.end(), r.command) == commands.end()) commands.push_back(r.command);
  md << "Measured by";
  for (std::size_t k = 0; k < commands.size(); ++k) md << (k ? " and " : " ") << "`" << commands[k] << "`";
  md << " " << trees(results) << ". The report, its tables and plots: [docs/bench/index.md](bench/index.md).\n\n";
  md << "| suite | goal | in every row | worst | verdict |\n|---|---|---|--:|---|\n";
  for (const Result& r : results)
    for (const Goal& g : r.suite->goals) {
      const Verdict v = judge(g, r.rows);
      md << "| `" << r.suite->name << "` | " << md_cell(g.text) << " | `" << g.row << "`"
         << (g.where.empty() ? "" : " with " + g.where + " " + g.is) << ": `" << g.metric << "` "
         << (g.at_least ? ">=" : "<=") << " " << text(g.bound) << " | "
         << (v.rows == 0 ? "" : text(v.worst) + " (" + std::to_string(v.rows) + (v.rows == 1 ? " row)" : " rows)"))
         << " | "
         << (!r.error.empty() ? "the suite failed"
             : v.rows == 0    ? "not measured"
             : v.met()        ? "met"
                              : "**not met**")
         << " |\n";
    }
  return md.str();
}

void write_index(const fs::path& dir, const std::vector<Result>& results, const std::string& redrawn_by) {
  std::ostringstream md;
  md << "# hcosim benchmark results\n\n";
  std::vector<std::string> commands;
  for (const Result& r : results)
    if (std::find(commands.begin(), commands.end(), r.command) == commands.end()) commands.push_back(r.command);
  md << "Measured by";
  for (std::size_t k = 0; k < commands.size(); ++k) md << (k ? " and " : " ") << "`" << commands[k] << "`";
  md << " " << trees(results);
  if (!redrawn_by.empty()) md << " (this report drawn again from its JSON files by `" << redrawn_by << "`)";
  md << ". Every figure below is measured on the machine described at the end; times are medians over repeats or "
        "percentiles over every sample, as each table says, and every ratio to a peer (bare Fast DDS, MuJoCo, OpenCV) "
        "compares two measurements taken in the same run.\n\n";
  md << "| suite | what it measures | rows | wall time (s) | goals |\n|---|---|--:|--:|---|\n";
  for (const Result& r : results) {
    std::string goals;
    for (const Goal& g : r.suite->goals) {
      const Verdict v = judge(g, r.rows);
      goals += (goals.empty() ? "" : "; ") + g.text + ": " +
               (v.rows == 0 ? "not measured"
                : v.met()   ? "met"
                            : "**not met**");
    }
    md << "| [" << r.suite->name << "](#" << r.suite->name << ") | " << md_cell(r.suite->what) << " | " << r.rows.size()
       << " | " << (std::isnan(r.seconds) ? "" : text(std::round(r.seconds))) << " | "
       << (r.error.empty() ? goals : "failed: " + md_cell(r.error)) << " |\n";
  }
  md << "\n";
  for (const Result& r : results) {
    md << "## " << r.suite->name << "\n\n" << r.suite->what << ". Full rows: `" << r.suite->name << ".json`.\n\n";
    if (!r.error.empty()) md << "**The suite failed:** " << r.error << "\n\n";
    for (const Goal& g : r.suite->goals) goal(md, g, r.rows);
    if (!r.suite->goals.empty()) md << "\n";
    std::vector<std::string> names;
    for (const Row& row : r.rows)
      if (std::find(names.begin(), names.end(), row.name) == names.end()) names.push_back(row.name);
    for (const std::string& name : names) {
      std::string caption = "Rows named `" + name + "`.";
      for (const Table& t : r.suite->tables)
        if (t.row == name) caption = t.caption;
      md << "### " << name << "\n\n" << caption << "\n\n";
      std::vector<const Row*> rows;
      for (const Row& row : r.rows)
        if (row.name == name) rows.push_back(&row);
      table(md, rows);
      for (const Figure& f : r.figures)
        if (f.row == name)
          md << "![" << f.caption << "](" << f.file.filename().string() << ")\n\n*" << f.caption << ".*\n\n";
    }
  }
  // Each suite records when it started: the date row spans them.
  const auto without_date = [](Machine m) {
    m.erase(std::remove_if(m.begin(), m.end(), [](const auto& kv) { return kv.first == "date"; }), m.end());
    return m;
  };
  const auto date_of = [](const Machine& m) {
    for (const auto& [k, v] : m)
      if (k == "date") return v;
    return std::string();
  };
  md << "## Machine\n\n| | |\n|---|---|\n";
  const Machine first = results.empty() ? machine() : results.front().machine;
  std::string earliest = date_of(first), latest = earliest;  // ISO 8601 dates sort as text
  for (const Result& r : results)
    earliest = std::min(earliest, date_of(r.machine)), latest = std::max(latest, date_of(r.machine));
  for (const auto& [k, v] : first) {
    std::string value = v;
    if (k == "date" && earliest != latest) value = "suites started from " + earliest + " to " + latest;
    md << "| " << k << " | " << md_cell(value) << " |\n";
  }
  for (const Result& r : results)
    if (without_date(r.machine) != without_date(first))
      md << "\n`" << r.suite->name << "` ran on another machine: see `" << r.suite->name << ".json`.\n";
  const fs::path file = dir / "index.md";
  std::ofstream(file) << md.str();
  std::cout << "wrote " << file.string() << "\n";
}

}  // namespace hcosim::services::bench
