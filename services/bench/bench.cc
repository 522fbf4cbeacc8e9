// hcosim bench: suites that measure speed against error, written as
// DIR/SUITE.json: {"suite", "description", "machine", "rows": [{"name",
// "params", "metrics"}]}, plots as DIR/SUITE_ROW_*.png, and DIR/index.md
// reporting the suites of the run (bench_report.cc). Metric names carry their unit (p99_us,
// ms_per_sim_s, rel_error, ...).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <variant>

#include "adapters/json.h"
#include "services/bench/bench.h"
#include "services/runtime/participant.h"

namespace fs = std::filesystem;

namespace hcosim::services::bench {
namespace {

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {dds_suite(),      massspring_suite(), haptic_suite(),   hybrid_suite(),
                                         rigid_suite(),    contact_suite(),    tracking_suite(), arview_suite(),
                                         foxglove_suite(), soak_suite()};
  return all;
}

void write_json(const fs::path& dir, const Result& r) {
  adapters::Json j;
  j["suite"] = r.suite->name;
  j["description"] = r.suite->what;
  j["machine"] = adapters::Json::object();
  for (const auto& [k, v] : r.machine) j["machine"][k] = v;
  j["command"] = r.command;
  j["commit"] = r.tree.commit;
  j["clean"] = r.tree.clean;
  j["seconds"] = r.seconds;
  j["rows"] = adapters::Json::array();
  for (const auto& row : r.rows) {
    adapters::Json out;
    out["name"] = row.name;
    out["params"] = adapters::Json::object();
    for (const auto& [k, v] : row.params) std::visit([&, key = k](const auto& x) { out["params"][key] = x; }, v);
    out["metrics"] = adapters::Json::object();
    for (const auto& [k, v] : row.metrics) out["metrics"][k] = v;
    j["rows"].push_back(std::move(out));
  }
  const fs::path file = dir / (std::string(r.suite->name) + ".json");
  std::ofstream(file) << adapters::json_line(j) << "\n";
  std::cout << "wrote " << file.string() << "\n";
}

// A suite's result as write_json wrote it (null: a metric not measured).
Result read_json(const fs::path& file, const Suite& s) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const adapters::Json doc = adapters::parse_json(text.str(), file.string());
  const auto number = [](const adapters::Json& v) { return v.is_number() ? v.get<double>() : NAN; };
  Result r{&s, {}, {}, doc.value("command", std::string("a run that did not record its command")), {}, {}, NAN, ""};
  r.tree.commit = doc.value("commit", r.tree.commit);
  r.tree.clean = doc.value("clean", false);
  // Each optional part is held first: a range over a temporary's items() would dangle.
  const adapters::Json none = adapters::Json::object(), machine = doc.value("machine", none),
                       rows = doc.value("rows", adapters::Json::array());
  for (const auto& [k, v] : machine.items()) r.machine.emplace_back(k, v.get<std::string>());
  if (doc.contains("seconds")) r.seconds = number(doc["seconds"]);
  for (const adapters::Json& row : rows) {
    Row out{row.at("name").get<std::string>(), {}, {}};
    const adapters::Json params = row.value("params", none), metrics = row.value("metrics", none);
    for (const auto& [k, v] : params.items()) {
      if (v.is_string())
        out.params.emplace_back(k, v.get<std::string>());
      else
        out.params.emplace_back(k, number(v));
    }
    for (const auto& [k, v] : metrics.items()) out.metrics.emplace_back(k, number(v));
    r.rows.push_back(std::move(out));
  }
  return r;
}

// The results in DIR's SUITE.json files, in the suites' order.
std::vector<Result> read_results(const fs::path& dir) {
  std::vector<Result> results;
  for (const Suite& s : suites()) {
    const fs::path file = dir / (std::string(s.name) + ".json");
    if (!fs::exists(file)) continue;
    try {
      results.push_back(read_json(file, s));
    } catch (const adapters::Json::exception& e) {
      // Valid JSON of another shape: a field missing or of the wrong type.
      throw std::runtime_error(file.string() + ": not a bench report: " + e.what());
    }
  }
  if (results.empty()) throw std::invalid_argument("no SUITE.json of any suite in " + dir.string());
  return results;
}

// A page's text with its drawn part (between kPageBegin and kPageEnd) in
// place of what stands there. Throws naming the page without them.
std::string with_part(const fs::path& page, const std::string& part) {
  std::ifstream in(page);
  if (!in) throw std::invalid_argument("cannot read " + page.string());
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  const std::string begin = std::string(kPageBegin) + "\n", end = std::string(kPageEnd) + "\n";
  const std::size_t b = s.find(begin), e = s.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b)
    throw std::invalid_argument(page.string() + ": no line '" + kPageBegin + "' followed by '" + kPageEnd + "'");
  return s.substr(0, b + begin.size()) + part + s.substr(e);
}

// `bench report --out DIR [--page PAGE]`: the plots and index.md again
// from the JSON files of an earlier run, measuring nothing, and PAGE's
// drawn part.
int report(const fs::path& dir, const fs::path& page) {
  std::vector<Result> results = read_results(dir);
  for (Result& r : results) r.figures = draw_plots(*r.suite, r.rows, dir);
  write_index(dir, results, "hcosim bench report --out " + dir.string());
  if (!page.empty()) {
    const std::string text = with_part(page, page_part(results));
    std::ofstream(page) << text;
    std::cout << "wrote " << page.string() << "\n";
  }
  return 0;
}

// `bench check --out DIR --page PAGE`: whether PAGE's drawn part is what
// DIR's JSON files give, writing nothing; the first line that differs.
int check(const fs::path& dir, const fs::path& page) {
  if (page.empty()) throw std::invalid_argument("bench check needs --page PAGE");
  const std::string want = with_part(page, page_part(read_results(dir)));
  std::ifstream in(page);
  std::stringstream text;
  text << in.rdbuf();
  if (text.str() == want) {
    std::cout << page.string() << ": its drawn part is what " << dir.string() << "/*.json give\n";
    return 0;
  }
  std::istringstream a(text.str()), b(want);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool more_a = bool(std::getline(a, la)), more_b = bool(std::getline(b, lb));
    if (!more_a && !more_b) break;
    if (la != lb || more_a != more_b) {
      std::cerr << page.string() << ":" << line << ": is\n  " << (more_a ? la : "(the end)") << "\nbut " << dir.string()
                << "/*.json give\n  " << (more_b ? lb : "(the end)") << "\n(hcosim bench report --out " << dir.string()
                << " --page " << page.string() << " draws it)\n";
      break;
    }
  }
  return 1;
}

struct BenchOptions {
  std::string which, out, page, work;
  bool quick = false;
  int domain = -1;  // -1: a domain of its own
};

int run(const BenchOptions& o) {
  const std::string& which = o.which;
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
  if (o.out.empty()) throw std::invalid_argument("bench needs --out DIR");
  const fs::path dir = o.out;
  if (which == "report") return report(dir, o.page);
  if (which == "check") return check(dir, o.page);
  if (chosen.empty()) throw std::invalid_argument("unknown suite '" + which + "' (suites: " + names + ", all)");
  fs::create_directories(dir);
  Context c;
  c.quick = o.quick;
  // Its own domain unless told: a benchmark must not hear a running
  // deployment. 215 and over (with the bare pair's next one, 230 at most)
  // keep its UDP ports above Linux's ephemeral range (32768 to 60999),
  // where another process's socket can take a domain's discovery port.
  c.domain = o.domain >= 0 ? o.domain : 215 + int(getpid() % 15);
  c.out = dir;
  c.work = o.work.empty() ? fs::temp_directory_path() / ("hcosim_bench_" + std::to_string(getpid())) : fs::path(o.work);
  fs::create_directories(c.work);
  progress("the suites' runs and logs: " + c.work.string());
  // The command in its synopsis' order, as the report names it.
  const std::string command = "hcosim bench " + which + (o.quick ? " --quick" : "") +
                              (o.domain >= 0 ? " --domain " + std::to_string(o.domain) : "") + " --out " + o.out;
  // Asked before anything is written: the run's own files are not the tree's changes.
  const Provenance tree = provenance();
  std::vector<Result> results;
  const auto begin = std::chrono::steady_clock::now();
  const auto since = [](auto t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); };
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const Suite& s = *chosen[k];
    progress("[" + std::to_string(k + 1) + "/" + std::to_string(chosen.size()) + "] " + s.name + ": " + s.what);
    const auto t0 = std::chrono::steady_clock::now();
    Result r{&s, {}, {}, command, machine(), tree, NAN, ""};
    try {
      r.rows = s.run(c);
      r.seconds = since(t0);
      r.figures = draw_plots(s, r.rows, dir);
      write_json(dir, r);
    } catch (const std::exception& e) {
      // One suite's failure must not cost the others' figures.
      if (chosen.size() == 1) throw;
      r.error = e.what();
      progress(std::string(s.name) + " failed: " + e.what());
    }
    progress(std::string(s.name) + " took " + text(std::round(since(t0))) + " s; " + text(std::round(since(begin))) +
             " s so far");
    results.push_back(std::move(r));
  }
  write_index(dir, results);
  for (const Result& r : results)
    if (!r.error.empty()) return 1;
  // A folder of its own is kept only when a suite failed, for its logs.
  if (o.work.empty()) fs::remove_all(c.work);
  return 0;
}

}  // namespace

Provenance provenance() {
  const auto git = [](const std::string& args) {
    std::string out;
    if (FILE* f = popen(("git -C '" + std::string(HCOSIM_SOURCE_DIR) + "' " + args + " 2>/dev/null").c_str(), "r")) {
      char buf[4096];
      for (std::size_t n; (n = fread(buf, 1, sizeof buf, f)) > 0;) out.append(buf, n);
      if (pclose(f) != 0) return std::string("\x01");  // git failed
    }
    return out;
  };
  Provenance p;
  const std::string head = git("rev-parse HEAD"), status = git("status --porcelain");
  if (head.size() > 1 && head[0] != '\x01') p.commit = head.substr(0, head.find('\n'));
  p.clean = p.commit != "unknown" && status.empty();
  return p;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

void add_bench(CLI::App& app, runtime::Command& chosen) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* c = app.add_subcommand("bench",
                                   "run one benchmark suite or all of them (the soak among them takes half an hour); "
                                   "write DIR/SUITE.json per suite, its plots, and DIR/index.md, the report "
                                   "(docs/PERFORMANCE.md); 'list' names the suites, 'report' redraws DIR's report "
                                   "(and with --page, that page's drawn part), 'check' says whether --page's drawn "
                                   "part is DIR's");
  c->add_option("SUITE|all|list|report|check", o->which, "what to run")->required();
  c->add_flag("--quick", o->quick, "shorter runs, for tests");
  c->add_option("--domain", o->domain, "DDS domain id (default: one of 215..229, of its own)")
      ->option_text("D")
      ->check(CLI::Range(0, adapters::kMaxDomain));
  c->add_option("--out", o->out, "the folder for the figures and the report")->option_text("DIR");
  c->add_option("--work", o->work,
                "where the suites run their processes and keep their logs (default: a new folder in /tmp, removed "
                "unless a suite fails)")
      ->option_text("DIR");
  c->add_option("--page", o->page, "report, check: the page whose drawn part the report gives (docs/PERFORMANCE.md)")
      ->option_text("PAGE");
  c->callback([&chosen, o] { chosen = [o] { return run(*o); }; });
}

}  // namespace hcosim::services::bench
