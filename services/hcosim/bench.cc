// hcosim bench: suites that measure speed against error, written as
// DIR/SUITE.json: {"suite", "description", "machine", "rows": [{"name",
// "params", "metrics"}]}, plots as DIR/SUITE_ROW_*.png, and DIR/index.md
// reporting the suites of the run (bench_report.cc). Metric names carry their unit (p99_us,
// ms_per_sim_s, rel_error, ...).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <variant>

#include "bench.h"
#include "cli.h"
#include "json.h"

namespace fs = std::filesystem;

namespace hcosim::cli {
namespace {

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {dds_suite(),   massspring_suite(), haptic_suite(), hybrid_suite(),
                                         rigid_suite(), tracking_suite(),   arview_suite()};
  return all;
}

void write_json(const fs::path& dir, const Suite& s, const std::vector<Row>& rows) {
  Json j;
  j.begin_object().key("suite").value(s.name).key("description").value(s.what).key("machine").begin_object();
  for (const auto& [k, v] : machine()) j.key(k).value(v);
  j.end_object().key("rows").begin_array();
  for (const auto& r : rows) {
    j.begin_object().key("name").value(r.name).key("params").begin_object();
    for (const auto& [k, v] : r.params) {
      j.key(k);
      std::visit([&](const auto& x) { j.value(x); }, v);
    }
    j.end_object().key("metrics").begin_object();
    for (const auto& [k, v] : r.metrics) j.key(k).value(v);
    j.end_object().end_object();
  }
  j.end_array().end_object();
  const fs::path file = dir / (std::string(s.name) + ".json");
  std::ofstream(file) << j.str() << "\n";
  std::cout << "wrote " << file.string() << "\n";
}

}  // namespace

int bench(const std::vector<std::string>& argv) {
  const Args a = parse(argv, {"--out", "--domain"}, {"--quick"});
  if (a.positional.size() != 1) throw std::invalid_argument("bench needs one SUITE (or 'all', or 'list')");
  const std::string which = a.positional[0];
  if (which == "list") {
    for (const auto& s : suites()) std::cout << s.name << "\t" << s.what << "\n";
    return 0;
  }
  std::vector<const Suite*> chosen;
  std::string names;
  for (const auto& s : suites()) {
    names += (names.empty() ? "" : ", ") + std::string(s.name);
    if (which == "all" || which == s.name) chosen.push_back(&s);
  }
  if (chosen.empty()) throw std::invalid_argument("unknown suite '" + which + "' (suites: " + names + ", all)");
  if (!a.has("--out")) throw std::invalid_argument("bench needs --out DIR");
  const fs::path dir = a.get("--out", "");
  fs::create_directories(dir);
  Context c;
  c.quick = a.switches.count("--quick") > 0;
  // Its own domain unless told: a benchmark must not hear a running deployment.
  c.domain = a.has("--domain") ? domain_of(a) : 200 + int(getpid() % 30);
  c.out = dir;
  std::string command = "hcosim bench";
  for (const auto& arg : argv) command += " " + arg;
  std::vector<Result> results;
  const auto begin = std::chrono::steady_clock::now();
  const auto since = [](auto t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); };
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const Suite& s = *chosen[k];
    progress("[" + std::to_string(k + 1) + "/" + std::to_string(chosen.size()) + "] " + s.name + ": " + s.what);
    const auto t0 = std::chrono::steady_clock::now();
    Result r{&s, {}, {}, 0, ""};
    try {
      r.rows = s.run(c);
      r.figures = draw_plots(s, r.rows, dir);
      write_json(dir, s, r.rows);
    } catch (const std::exception& e) {
      // One suite's failure must not cost the others' figures.
      if (chosen.size() == 1) throw;
      r.error = e.what();
      progress(std::string(s.name) + " failed: " + e.what());
    }
    r.seconds = since(t0);
    progress(std::string(s.name) + " took " + text(std::round(r.seconds)) + " s; " + text(std::round(since(begin))) +
             " s so far");
    results.push_back(std::move(r));
  }
  write_index(dir, command, results);
  for (const Result& r : results)
    if (!r.error.empty()) return 1;
  return 0;
}

}  // namespace hcosim::cli
