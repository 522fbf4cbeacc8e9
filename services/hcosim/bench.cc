// hcosim bench: suites that measure speed against error, written as
// DIR/SUITE.json: {"suite", "machine", "rows": [{"name", "params", "metrics"}]}.
// Metric names carry their unit (p99_us, ms_per_sim_s, rel_error, ...).
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <thread>
#include <variant>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "bench.h"
#include "cli.h"
#include "json.h"
#include "service.h"

namespace fs = std::filesystem;

namespace hcosim::cli {
namespace {

// ---- dds: 1 kHz HapticState -> ForceFeedback round trip between processes.

using namespace eprosima::fastdds::dds;

// The far end's endpoints: hcosim's runtime, or Fast DDS with nothing of ours.
struct Pong {
  std::function<bool()> wait;  // an unread HapticState is there
  std::function<bool(HapticState&)> take;
  std::function<void(ForceFeedback&)> write;
};

// Bare Fast DDS: default participant QoS (builtin transports), the same
// types, BEST_EFFORT and KEEP_LAST 1 set in code.
struct Bare {
  DomainParticipant* participant;
  DataWriter* writer;
  DataReader* reader;

  template <class Out, class In>
  static Bare make(int domain, const char* out_topic, const char* in_topic) {
    Bare b;
    b.participant = DomainParticipantFactory::get_instance()->create_participant(domain, PARTICIPANT_QOS_DEFAULT);
    if (!b.participant) throw std::runtime_error("bare: cannot create participant");
    TypeSupport out_ts(new typename rt::TopicOf<Out>::PubSub()), in_ts(new typename rt::TopicOf<In>::PubSub());
    out_ts.register_type(b.participant, rt::TopicOf<Out>::type_name);
    in_ts.register_type(b.participant, rt::TopicOf<In>::type_name);
    Topic* ot = b.participant->create_topic(out_topic, rt::TopicOf<Out>::type_name, TOPIC_QOS_DEFAULT);
    Topic* it = b.participant->create_topic(in_topic, rt::TopicOf<In>::type_name, TOPIC_QOS_DEFAULT);
    DataWriterQos wq = DATAWRITER_QOS_DEFAULT;
    wq.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
    wq.history().kind = KEEP_LAST_HISTORY_QOS;
    wq.history().depth = 1;
    DataReaderQos rq = DATAREADER_QOS_DEFAULT;
    rq.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
    rq.history().kind = KEEP_LAST_HISTORY_QOS;
    rq.history().depth = 1;
    b.writer = b.participant->create_publisher(PUBLISHER_QOS_DEFAULT)->create_datawriter(ot, wq);
    b.reader = b.participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT)->create_datareader(it, rq);
    return b;
  }
  void destroy() {
    participant->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant);
  }
};

const eprosima::fastrtps::Duration_t kWait = rt::to_dds(std::chrono::milliseconds(100));

int pong_loop(Pong& p, std::int64_t end) {
  HapticState in;
  ForceFeedback out;
  out.source("bench");
  while (!rt::stop_requested() && rt::mono_ns() < end) {
    if (!p.wait()) continue;
    while (p.take(in)) {
      out.device(in.device());
      out.answers_seq(in.seq());
      out.force().z(-in.position().z() * 500.0);
      p.write(out);
    }
  }
  return 0;
}

// Sends HapticState at 1 kHz for `seconds`, waiting up to 10 ms for the
// ForceFeedback that answers each one.
template <class Wait, class Take, class Write>
Rtt ping(double seconds, Wait&& wait, Take&& take, Write&& write) {
  Rtt r;
  HapticState s;
  s.device("bench");
  s.orientation().w(1.0);
  const std::int64_t period = 1'000'000, start = rt::mono_ns();
  const std::uint64_t n = std::uint64_t(seconds * 1000);
  for (std::uint64_t k = 0; k < n; ++k) {
    const std::int64_t due = start + std::int64_t(k) * period;
    timespec ts{time_t(due / 1'000'000'000), long(due % 1'000'000'000)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
    s.seq(k);
    s.position().z(1e-3 * double(k % 10));
    const std::int64_t t0 = rt::mono_ns();
    write(s);
    ++r.sent;
    bool answered = false;
    while (!answered && rt::mono_ns() - t0 < 10'000'000)
      if (wait()) answered = take(k);
    if (answered) r.us.add((rt::mono_ns() - t0) * 1e-3);
    else ++r.lost;
  }
  return r;
}

}  // namespace

pid_t start_peer(const std::string& impl, int domain, double seconds) {
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const pid_t pid = fork();
  if (pid == 0) {
    execl(self.c_str(), self.c_str(), "bench-peer", "--impl", impl.c_str(), "--domain",
          std::to_string(domain).c_str(), "--duration", std::to_string(seconds + 30).c_str(), nullptr);
    _exit(127);
  }
  return pid;
}

void stop_peer(pid_t pid) {
  kill(pid, SIGTERM);
  int status;
  waitpid(pid, &status, 0);
}

Rtt bare_rtt(int domain, double seconds) {
  const pid_t peer = start_peer("bare", domain, seconds);
  Bare b = Bare::make<HapticState, ForceFeedback>(domain, "HapticState", "ForceFeedback");
  PublicationMatchedStatus pm;
  SubscriptionMatchedStatus sm;
  const std::int64_t deadline = rt::mono_ns() + 10'000'000'000;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    b.writer->get_publication_matched_status(pm);
    b.reader->get_subscription_matched_status(sm);
  } while ((pm.current_count < 1 || sm.current_count < 1) && rt::mono_ns() < deadline);
  ForceFeedback f;
  SampleInfo info;
  Rtt r = ping(
      seconds, [&] { return b.reader->wait_for_unread_message(rt::to_dds(std::chrono::milliseconds(10))); },
      [&](std::uint64_t k) {
        bool hit = false;
        while (b.reader->take_next_sample(&f, &info) == ReturnCode_t::RETCODE_OK)
          hit = hit || (info.valid_data && f.answers_seq() == k);
        return hit;
      },
      [&](HapticState& s) { b.writer->write(&s); });
  b.destroy();
  stop_peer(peer);
  return r;
}

namespace {

Row rtt_row(const std::string& impl, const Rtt& r) {
  Row row{"rtt", {{"impl", impl}, {"rate_hz", 1000.0}, {"payload", std::string("HapticState/ForceFeedback")}}, {}};
  row.metrics = {{"p50_us", r.us.percentile(0.5)},
                 {"p99_us", r.us.percentile(0.99)},
                 {"p999_us", r.us.percentile(0.999)},
                 {"loss_ratio", r.sent ? double(r.lost) / double(r.sent) : 1.0},
                 {"samples", double(r.sent)}};
  return row;
}

std::vector<Row> dds_rows(const Context& c) {
  const double seconds = c.quick ? 5 : 30;
  std::vector<Row> rows;
  // Bare first, then hcosim, in the same run: only their ratio is meaningful.
  progress("dds rtt bare Fast DDS, " + std::to_string(int(seconds)) + " s at 1 kHz");
  rows.push_back(rtt_row("bare", bare_rtt(c.domain, seconds)));
  {
    progress("dds rtt hcosim runtime, " + std::to_string(int(seconds)) + " s at 1 kHz");
    const pid_t peer = start_peer("hcosim", c.domain, seconds);
    Rtt r;
    {
      rt::Participant p(c.domain, "bench");
      rt::Writer<HapticState> w(p);
      rt::Reader<ForceFeedback> rd(p, [](const ForceFeedback& s) { return validate(s); });
      const std::int64_t deadline = rt::mono_ns() + 10'000'000'000;
      while ((w.matched() < 1 || rd.matched() < 1) && rt::mono_ns() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      r = ping(
          seconds, [&] { return rd.wait(std::chrono::milliseconds(10)); },
          [&](std::uint64_t k) {
            bool hit = false;
            rd.take([&](const ForceFeedback& f) { hit = hit || f.answers_seq() == k; });
            return hit;
          },
          [&](HapticState& s) { w.write(s); });
    }
    stop_peer(peer);
    Row row = rtt_row("hcosim", r);
    const double bare_p99 = rows[0].metrics[1].second, bare_p50 = rows[0].metrics[0].second;
    row.metrics.push_back({"p50_ratio_to_bare", row.metrics[0].second / bare_p50});
    row.metrics.push_back({"p99_ratio_to_bare", row.metrics[1].second / bare_p99});
    rows.push_back(row);
  }
  return rows;
}

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {
      {"dds", "1 kHz HapticState/ForceFeedback round trip between two processes: hcosim runtime vs bare Fast DDS",
       dds_rows},
      massspring_suite(),
      haptic_suite(),
      hybrid_suite(),
      rigid_suite(),
      tracking_suite(),
      arview_suite(),
  };
  return all;
}

// ---- report

std::string first_line_with(const char* path, const std::string& prefix) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) {
      const auto colon = line.find(':');
      return colon == std::string::npos ? line : line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  return "";
}

void write_machine(Json& j) {
  utsname u{};
  uname(&u);
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  j.begin_object();
  j.key("host").value(host).key("cpu").value(first_line_with("/proc/cpuinfo", "model name"));
  j.key("cores").value(std::int64_t(std::thread::hardware_concurrency()));
  j.key("memory").value(first_line_with("/proc/meminfo", "MemTotal"));
  j.key("kernel").value(std::string(u.sysname) + " " + u.release);
  j.key("compiler").value(__VERSION__).key("date").value(date);
  j.end_object();
}

void write_report(const fs::path& dir, const Suite& s, const std::vector<Row>& rows) {
  Json j;
  j.begin_object().key("suite").value(s.name).key("description").value(s.what).key("machine");
  write_machine(j);
  j.key("rows").begin_array();
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
  for (const Suite* s : chosen) write_report(dir, *s, s->run(c));
  return 0;
}

int bench_peer(const std::vector<std::string>& argv) {
  const Args a = parse(argv, {"--impl", "--domain", "--duration"}, {});
  const int domain = domain_of(a);
  const std::int64_t end = rt::mono_ns() + std::int64_t(a.number("--duration", 60) * 1e9);
  rt::install_stop_handlers();
  if (a.get("--impl", "") == "bare") {
    Bare b = Bare::make<ForceFeedback, HapticState>(domain, "ForceFeedback", "HapticState");
    SampleInfo info;
    Pong p{[&] { return b.reader->wait_for_unread_message(kWait); },
           [&](HapticState& s) {
             while (b.reader->take_next_sample(&s, &info) == ReturnCode_t::RETCODE_OK)
               if (info.valid_data) return true;
             return false;
           },
           [&](ForceFeedback& f) { b.writer->write(&f); }};
    const int code = pong_loop(p, end);
    b.destroy();
    return code;
  }
  rt::Options o;
  o.name = "bench_peer";
  o.domain = domain;
  o.rate_hz = 1000;
  o.step_s = 0.001;
  o.qos_file = rt::default_qos_file();
  rt::Service svc(o);
  rt::Reader<HapticState> r = svc.reader<HapticState>();
  rt::Writer<ForceFeedback> w = svc.writer<ForceFeedback>();
  Pong p{[&] { return r.wait(std::chrono::milliseconds(100)); },
         [&](HapticState& s) {
           bool got = false;
           r.take([&](const HapticState& x) { s = x, got = true; });
           return got;
         },
         [&](ForceFeedback& f) { w.write(f); }};
  return pong_loop(p, end);
}

}  // namespace hcosim::cli
