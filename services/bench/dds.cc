// bench dds: the transport, hcosim's runtime against bare Fast DDS in the
// same run.
//
// rtt: 1 kHz HapticState -> ForceFeedback round trips between two
//   processes; the far end answers each sample at once (`hcosim bench-peer`).
// mesh_pub: DeformedMesh of `vertices` vertices (positions and normals,
//   24 bytes a vertex) written at 60 Hz by this process to `subscribers`
//   reader processes. Latency is the reader's CLOCK_REALTIME at take minus
//   the sample's stamp.wall_time_ns set just before write, pooled over the
//   readers; loss_ratio counts samples written but not taken; cpu_pct is the
//   CPU time of the writer's and every reader's process over the writing
//   window, in % of one core. Each configuration runs in rounds (2 of 60
//   samples quick, 6 of 200 full), the impls taking turns to go first;
//   figures pool every round. p99_split_ratio compares one impl's p99 over
//   its odd rounds with that over its even ones (the larger over the
//   smaller): a ratio to bare within it is within the machine's noise. `impl` hcosim: runtime::Participant with
//   deploy/qos.xml's transports and "state" profile, runtime::Writer, runtime::Reader
//   (which validates every sample). `impl` bare: Fast DDS alone, the same
//   transports (shared memory with an 8 MiB segment, UDPv4) and QoS
//   (RELIABLE, VOLATILE, writer and readers KEEP_LAST 16) set in code, the
//   same bytes. Each round starts with warm-up samples, not counted, until
//   every reader has taken one (startup_ms, the slowest round's) and half
//   a second more: loss and latency are a running reader's.
// rtt_hosts, mesh_hosts, frame_hosts: the same between hosts made of
//   Linux network namespaces on one bridge (Hosts; each its own address
//   and /dev/shm, so UDP only), where this machine can make them: the round
//   trips between two hosts, 10^5-vertex meshes from one host to a reader
//   on each of two others, a camera's 640x480 bgr8 frames at 30 Hz from
//   one host to a reader on another. Every participant has the rig's network (a deployment's
//   `network: {}` defaults: its host's address the only UDP interface, 4
//   MiB socket buffers), bare Fast DDS's mesh endpoints the same buffers
//   and interface; this process's side runs on a thread moved into the
//   first host.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <thread>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "adapters/validate.h"
#include "services/bench/bench.h"
#include "services/bench/harness.h"
#include "services/bench/hosts.h"
#include "services/bench/peer.h"
#include "services/runtime/realtime.h"
#include "services/runtime/service.h"

namespace fs = std::filesystem;

namespace hcosim::services::bench {
namespace {

using namespace eprosima::fastdds::dds;

// On host `k` of `hosts`: the arguments that give a peer the rig's network there.
std::vector<std::string> rig_args(const Hosts& hosts, int k) {
  return {"--deployment", hosts.rig().string(), "--host", hosts.name(k)};
}

// The network of this process's side on host `k` of `hosts`.
runtime::Network rig_network(const Hosts& hosts, int k) {
  return runtime::network_of(adapters::load_deployment(hosts.rig().string()), hosts.name(k));
}

// ---- rtt

Row rtt_row(const std::string& impl, const Rtt& r) {
  Row row{"rtt", {{"impl", impl}, {"rate_hz", 1000.0}, {"payload", std::string("HapticState/ForceFeedback")}}, {}};
  row.metrics = {{"p50_us", r.us.percentile(0.5)},
                 {"p99_us", r.us.percentile(0.99)},
                 {"p999_us", r.us.percentile(0.999)},
                 {"loss_ratio", r.sent ? double(r.lost) / double(r.sent) : 1.0},
                 {"samples", double(r.sent)}};
  return row;
}

// Round trips from this thread against an hcosim peer; with `hosts`, this
// thread on host 0 and the peer on host 1, each with the rig's network.
// Adds to `ours` its p50 and p99 (its first two metrics) over `bare`'s.
void add_ratios(Row& ours, const Row& bare) {
  ours.metrics.push_back({"p50_ratio_to_bare", ours.metrics[0].second / bare.metrics[0].second});
  ours.metrics.push_back({"p99_ratio_to_bare", ours.metrics[1].second / bare.metrics[1].second});
}

Rtt hcosim_rtt(int domain, double seconds, const Hosts* hosts = nullptr) {
  const pid_t peer = hosts ? start_peer("hcosim", domain, seconds, 0, hosts->exec(1), rig_args(*hosts, 1))
                           : start_peer("hcosim", domain, seconds);
  Rtt r;
  {
    runtime::Participant p(domain, "bench", runtime::default_qos_file(), nullptr, false, {},
                           hosts ? rig_network(*hosts, 0) : runtime::Network{});
    runtime::Writer<HapticState> w(p);
    runtime::Reader<ForceFeedback> rd(p, [](const ForceFeedback& s) { return adapters::validate(s); });
    await_match([&] { return std::min(w.matched(), rd.matched()); }, 1);
    r = ping(
        seconds, [&] { return rd.wait(std::chrono::milliseconds(10)); },
        [&](std::uint64_t k) {
          bool hit = false;
          rd.take([&](const ForceFeedback& f) { hit = hit || f.answers_seq() == k; });
          return hit;
        },
        [&](HapticState& s) { w.write(s); });
  }
  stop(peer);
  return r;
}

// ---- mesh_pub

constexpr double kMeshRateHz = 60;
constexpr int kReaderDepth = 16;
constexpr int kWriterDepth = 16;  // deploy/qos.xml's "state" writers

// A sheet of `vertices` vertices, 1 mm apart, normals up.
DeformedMesh mesh_sample(int vertices) {
  DeformedMesh m;
  m.mesh("bench");
  m.topology_version(1);
  m.positions().resize(3 * std::size_t(vertices));
  m.normals().assign(3 * std::size_t(vertices), 0.0f);
  const int side = int(std::ceil(std::sqrt(double(vertices))));
  for (int i = 0; i < vertices; ++i) {
    m.positions()[3 * i] = 1e-3f * float(i % side);
    m.positions()[3 * i + 1] = 1e-3f * float(i / side);
    m.normals()[3 * i + 2] = 1.0f;
  }
  return m;
}

// The large samples of the suite, each a type's: meshes (mesh_pub,
// mesh_hosts) and camera frames (frame_hosts). A sample is a warm-up one
// (counted false: not measured, see ready()) or a counted one.
template <class T>
struct Large;

template <>
struct Large<DeformedMesh> {
  static constexpr const char* role = "mesh";
  static constexpr double rate_hz = kMeshRateHz;
  static DeformedMesh make(int vertices) { return mesh_sample(vertices); }
  static void vary(DeformedMesh& m, std::uint64_t step) { m.positions()[2] = 1e-4f * float(step % 100); }
  static void count(DeformedMesh& m, bool counted) { m.topology_version(counted ? 1 : 0); }
  static bool counted(const DeformedMesh& m) { return m.topology_version() != 0; }
};

// A camera's 640x480 bgr8 frames at 30 Hz, 921,600 bytes of pixels.
template <>
struct Large<CameraFrame> {
  static constexpr const char* role = "frame";
  static constexpr double rate_hz = 30;
  static CameraFrame make(int) {
    CameraFrame f;
    f.camera("bench");
    f.width(640);
    f.height(480);
    f.encoding("bgr8");
    f.fx(500), f.fy(500), f.cx(320), f.cy(240);
    f.data().assign(640 * 480 * 3, 128);
    return f;
  }
  static void vary(CameraFrame& f, std::uint64_t step) {
    f.frame(step);
    f.data()[0] = std::uint8_t(step);
  }
  // A frame's warm-up camera name: another instance, unmeasured.
  static void count(CameraFrame& f, bool counted) { f.camera(counted ? "bench" : "warm-up"); }
  static bool counted(const CameraFrame& f) { return f.camera().to_string() == "bench"; }
};

double cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// What one reader process saw: written by `bench-peer --role mesh` to its
// --out file as "received rejected cpu_s\n" and "seq latency_ms" a sample.
struct Seen {
  double received = 0, rejected = 0, cpu_s = 0;
  std::vector<std::uint64_t> seq;
  std::vector<double> ms;
};

Seen read_seen(const fs::path& file) {
  Seen s;
  std::ifstream in(file);
  if (!(in >> s.received >> s.rejected >> s.cpu_s))
    throw std::runtime_error("bench dds: a mesh reader wrote no result to " + file.string());
  std::uint64_t k;
  for (double v; in >> k >> v;) s.seq.push_back(k), s.ms.push_back(v);
  return s;
}

struct Writing {
  std::uint64_t written = 0, refused = 0;
  double cpu_s = 0, window_s = 0;
  bool acked = true;      // every reader acknowledged the last sample in time
  double startup_ms = 0;  // from the match until every reader took a sample
};

// The readers that have taken a warm-up sample: each says so with
// FILE.ready.
int ready(const std::vector<fs::path>& files) {
  int n = 0;
  for (const fs::path& f : files) n += fs::exists(f.string() + ".ready");
  return n;
}

// Warm-up samples (topology_version 0) are written from the match until
// every reader has taken one, and for kSettleSamples more: a reader process
// just started is still loading, discovering the other readers and
// allocating, and in its first ~0.4 s fell more than the writer's 16
// samples behind and lost some (10^5 vertices to 3 readers, both impls;
// 1000 vertices once on CI). That is start-up, reported as startup_ms; the
// counted samples measure a running reader.
constexpr int kSettleSamples = 30;

// Writes warm-up samples, then `count` counted ones at the type's rate;
// the writer's own CPU time over the counted window.
template <class T, class Matched, class Write, class Acked>
Writing write_large(int size, int count, const std::vector<fs::path>& readers, Matched&& matched, Write&& write,
                    Acked&& acked) {
  const int want = int(readers.size());
  await_match(matched, want);
  const std::string what = std::string(Large<T>::role) + " readers, ";
  if (matched() < want)
    throw std::runtime_error("bench dds: of " + std::to_string(want) + " " + what + std::to_string(matched()) +
                             " matched the writer in 10 s");
  T m = Large<T>::make(size);
  Writing w;
  const std::int64_t period = std::int64_t(1e9 / Large<T>::rate_hz);
  const auto put = [&](std::int64_t at, std::uint64_t step) {
    sleep_until(at);
    Large<T>::vary(m, step);  // no two samples alike
    m.stamp().step(step);
    m.stamp().sim_time_ns(std::int64_t(step) * period);
    m.stamp().wall_time_ns(runtime::wall_ns());
    return write(m);
  };
  Large<T>::count(m, false);
  const std::int64_t matched_at = runtime::mono_ns();
  int settle = kSettleSamples;
  for (std::uint64_t k = 0; settle > 0 && !runtime::stop_requested(); ++k) {
    put(matched_at + std::int64_t(k) * period, k);
    if (ready(readers) < want) {
      if (runtime::mono_ns() - matched_at > 10'000'000'000)
        throw std::runtime_error("bench dds: of " + std::to_string(want) + " matched " + what +
                                 std::to_string(ready(readers)) + " took a sample in 10 s");
      w.startup_ms = (runtime::mono_ns() - matched_at) * 1e-6;
    } else {
      --settle;
    }
  }
  Large<T>::count(m, true);
  const double cpu0 = cpu_s();
  const std::int64_t start = runtime::mono_ns() + period;
  for (int k = 0; k < count && !runtime::stop_requested(); ++k) {
    if (put(start + k * period, std::uint64_t(k)))
      ++w.written;
    else
      ++w.refused;
  }
  w.acked = acked();
  w.window_s = (runtime::mono_ns() - start) * 1e-9;
  w.cpu_s = cpu_s() - cpu0;
  return w;
}

template <class T>
pid_t start_reader(const std::string& impl, int domain, int count, const fs::path& out,
                   const std::vector<std::string>& on, const std::vector<std::string>& args) {
  std::vector<std::string> all = {"bench-peer",
                                  "--role",
                                  Large<T>::role,
                                  "--impl",
                                  impl,
                                  "--domain",
                                  std::to_string(domain),
                                  "--count",
                                  std::to_string(count),
                                  "--out",
                                  out.string(),
                                  "--duration",
                                  std::to_string(count / Large<T>::rate_hz + 30)};
  all.insert(all.end(), args.begin(), args.end());
  return start_self(on, all);
}

// Names the steps a reader never took, so that a loss can be told apart:
// a run of missing steps mid-stream is a writer history overrun (the reader
// fell 16 samples behind), missing last steps a reader stopped too early.
void say_missed(const std::string& what, int reader, int count, const Seen& s, bool acked) {
  std::vector<bool> got(std::size_t(count), false);
  for (std::uint64_t k : s.seq)
    if (k < std::uint64_t(count)) got[k] = true;
  std::string runs;
  for (int k = 0; k < count;) {
    if (got[std::size_t(k)]) {
      ++k;
      continue;
    }
    const int first = k;
    while (k < count && !got[std::size_t(k)]) ++k;
    runs += (runs.empty() ? "" : ", ") + std::to_string(first) + (k - 1 > first ? "-" + std::to_string(k - 1) : "");
  }
  progress("dds " + what + ": reader " + std::to_string(reader) + " missed step(s) " + runs + " of " +
           std::to_string(count) + (acked ? "" : "; the writer's wait for acknowledgements timed out"));
}

// One impl's samples over every round of a configuration.
struct MeshTotals {
  runtime::Window ms{1 << 20};
  runtime::Window half[2] = {runtime::Window{1 << 20}, runtime::Window{1 << 20}};  // odd and even rounds apart
  double written = 0, received = 0, refused = 0, rejected = 0, cpu_s = 0, window_s = 0;
  double startup_ms = 0;  // the slowest round's
};

// One round: `count` samples of `size` to `readers` fresh reader processes.
// With `hosts`, the writer is on host 0 (this thread's) and reader k on host k + 1.
template <class T>
void large_round(const Context& c, const std::string& impl, int size, int readers, int count, int round, MeshTotals& t,
                 const Hosts* hosts = nullptr) {
  const fs::path dir = c.work / (hosts ? "dds_hosts_run" : "dds_run");
  fs::create_directories(dir);
  std::vector<pid_t> pids;
  std::vector<fs::path> files;
  for (int k = 0; k < readers; ++k) {
    files.push_back(dir / (std::string(Large<T>::role) + "_" + impl + "_" + std::to_string(size) + "_" +
                           std::to_string(k) + ".txt"));
    fs::remove(files.back());
    fs::remove(files.back().string() + ".ready");
    pids.push_back(start_reader<T>(impl, c.domain, count, files.back(),
                                   hosts ? hosts->exec(k + 1) : std::vector<std::string>{},
                                   hosts ? rig_args(*hosts, k + 1) : std::vector<std::string>{}));
  }
  const auto ack = std::chrono::seconds(5);
  Writing w;
  if (impl == "bare") {
    DomainParticipant* p = bare_participant(c.domain, true, hosts ? rig_network(*hosts, 0) : runtime::Network{});
    DataWriterQos q = DATAWRITER_QOS_DEFAULT;
    q.reliability().kind = RELIABLE_RELIABILITY_QOS;
    q.durability().kind = VOLATILE_DURABILITY_QOS;
    q.history().kind = KEEP_LAST_HISTORY_QOS;
    q.history().depth = kWriterDepth;
    DataWriter* dw =
        p->create_publisher(PUBLISHER_QOS_DEFAULT)->create_datawriter(bare_topic<T>(p, runtime::TopicOf<T>::name), q);
    w = write_large<T>(
        size, count, files,
        [&] {
          PublicationMatchedStatus s;
          dw->get_publication_matched_status(s);
          return s.current_count;
        },
        [&](T& m) { return dw->write(&m); },
        [&] { return dw->wait_for_acknowledgments(runtime::to_dds(ack)) == ReturnCode_t::RETCODE_OK; });
    destroy_bare(p);
  } else {
    runtime::Participant p(c.domain, "bench", runtime::default_qos_file(), nullptr, false, {},
                           hosts ? rig_network(*hosts, 0) : runtime::Network{});
    runtime::Writer<T> dw(p);
    w = write_large<T>(
        size, count, files, [&] { return dw.matched(); }, [&](T& m) { return dw.write(m); },
        [&] { return dw.wait_acknowledged(ack); });
  }
  t.written += double(count) * readers, t.refused += double(w.refused), t.cpu_s += w.cpu_s, t.window_s += w.window_s;
  t.startup_ms = std::max(t.startup_ms, w.startup_ms);
  for (int k = 0; k < readers; ++k) {
    if (!reap(pids[std::size_t(k)], 5))
      throw std::runtime_error("bench dds: " + std::string(Large<T>::role) + " reader " + std::to_string(k) +
                               " failed; see " + files[std::size_t(k)].string());
    const Seen s = read_seen(files[std::size_t(k)]);
    if (s.received < count) say_missed(std::string(Large<T>::role) + " " + impl, k, count, s, w.acked);
    t.received += s.received, t.rejected += s.rejected, t.cpu_s += s.cpu_s;
    for (double v : s.ms) t.ms.add(v), t.half[round % 2].add(v);
  }
}

// What `readers` readers saw of large samples over every round.
std::vector<std::pair<std::string, double>> large_metrics(const MeshTotals& t) {
  return {{"p50_ms", t.ms.percentile(0.5)},
          {"p99_ms", t.ms.percentile(0.99)},
          {"loss_ratio", 1 - t.received / t.written},
          {"cpu_pct", 100 * t.cpu_s / t.window_s},
          {"samples", t.written},
          {"refused_writes", t.refused},
          {"rejected", t.rejected},
          {"startup_ms", t.startup_ms},
          // The same impl measured twice (odd rounds, even rounds): how far
          // apart two p99s of one thing fall on this machine.
          {"p99_split_ratio", std::max(t.half[0].percentile(0.99) / t.half[1].percentile(0.99),
                                       t.half[1].percentile(0.99) / t.half[0].percentile(0.99))}};
}

Row mesh_row(const std::string& impl, int vertices, int readers, const MeshTotals& t) {
  return {"mesh_pub",
          {{"vertices", double(vertices)},
           {"subscribers", double(readers)},
           {"impl", impl},
           {"rate_hz", kMeshRateHz},
           {"bytes", 24.0 * vertices}},
          large_metrics(t)};
}

Row frame_row(const std::string& impl, int readers, const MeshTotals& t) {
  const CameraFrame f = Large<CameraFrame>::make(0);
  return {"frame_hosts",
          {{"width", double(f.width())},
           {"height", double(f.height())},
           {"subscribers", double(readers)},
           {"impl", impl},
           {"rate_hz", Large<CameraFrame>::rate_hz},
           {"bytes", double(f.data().size())}},
          large_metrics(t)};
}

std::vector<Row> dds_rows(const Context& c) {
  const double seconds = c.quick ? 5 : 30;
  std::vector<Row> rows;
  // Bare first, then hcosim, in the same run: only their ratio is meaningful.
  progress("dds rtt bare Fast DDS, " + std::to_string(int(seconds)) + " s at 1 kHz");
  rows.push_back(rtt_row("bare", bare_rtt(c.domain, seconds)));
  progress("dds rtt hcosim runtime, " + std::to_string(int(seconds)) + " s at 1 kHz");
  rows.push_back(rtt_row("hcosim", hcosim_rtt(c.domain, seconds)));
  add_ratios(rows[1], rows[0]);

  // Rounds alternate which impl goes first, so that a machine growing
  // busier or quieter during a configuration favours neither.
  const int count = c.quick ? 60 : 200, rounds = c.quick ? 2 : 6;
  for (const int vertices : {1000, 10000, 100000})
    for (const int readers : {1, 3}) {
      MeshTotals bare_t, ours_t;
      for (int round = 0; round < rounds; ++round)
        for (const bool first : {true, false}) {
          const bool is_bare = first == (round % 2 == 0);
          const std::string impl = is_bare ? "bare" : "hcosim";
          progress("dds mesh_pub " + impl + ": " + std::to_string(vertices) + " vertices to " +
                   std::to_string(readers) + " reader(s), round " + std::to_string(round + 1) + " of " +
                   std::to_string(rounds) + ", " + std::to_string(count) + " samples at 60 Hz");
          large_round<DeformedMesh>(c, impl, vertices, readers, count, round, is_bare ? bare_t : ours_t);
        }
      const Row bare = mesh_row("bare", vertices, readers, bare_t);
      Row ours = mesh_row("hcosim", vertices, readers, ours_t);
      add_ratios(ours, bare);
      rows.push_back(bare);
      rows.push_back(ours);
    }
  return rows;
}

// One reader of mesh_pub, mesh_hosts or frame_hosts: takes T until the
// last of `count` arrives or it is stopped, then writes what it saw (see
// Seen).
template <class T>
int large_reader(const std::string& impl, int domain, int count, const fs::path& out, std::int64_t end,
                 const runtime::Network& network) {
  Seen seen;
  double cpu0 = -1;
  bool said = false;
  const auto got = [&](const T& m) {
    if (!Large<T>::counted(m)) {  // warm-up: tells the writer this reader takes samples (see ready())
      if (!said) said = bool(std::ofstream(out.string() + ".ready") << "taking\n");
      return false;
    }
    if (cpu0 < 0) cpu0 = cpu_s();
    ++seen.received;
    seen.seq.push_back(m.stamp().step());
    seen.ms.push_back((runtime::wall_ns() - m.stamp().wall_time_ns()) * 1e-6);
    return m.stamp().step() + 1 >= std::uint64_t(count);
  };
  bool last = false;
  if (impl == "bare") {
    DomainParticipant* p = bare_participant(domain, true, network);
    DataReaderQos q = DATAREADER_QOS_DEFAULT;
    q.reliability().kind = RELIABLE_RELIABILITY_QOS;
    q.durability().kind = VOLATILE_DURABILITY_QOS;
    q.history().kind = KEEP_LAST_HISTORY_QOS;
    q.history().depth = kReaderDepth;
    DataReader* r =
        p->create_subscriber(SUBSCRIBER_QOS_DEFAULT)->create_datareader(bare_topic<T>(p, runtime::TopicOf<T>::name), q);
    T m;
    SampleInfo info;
    while (!last && !runtime::stop_requested() && runtime::mono_ns() < end) {
      if (!r->wait_for_unread_message(runtime::to_dds(std::chrono::milliseconds(20)))) continue;
      while (r->take_next_sample(&m, &info) == ReturnCode_t::RETCODE_OK)
        if (info.valid_data) last = got(m) || last;
    }
    destroy_bare(p);
  } else {
    runtime::Participant p(domain, "bench_mesh_reader", runtime::default_qos_file(), nullptr, false, {}, network);
    runtime::Rejections rejected;
    runtime::Reader<T> r(
        p, [](const T& m) { return adapters::validate(m); }, &rejected, runtime::TopicOf<T>::qos, kReaderDepth);
    while (!last && !runtime::stop_requested() && runtime::mono_ns() < end) {
      if (r.wait(std::chrono::milliseconds(20))) r.take([&](const T& m) { last = got(m) || last; });
    }
    seen.rejected = double(rejected.count);
  }
  std::ofstream f(out);
  f << seen.received << " " << seen.rejected << " " << (cpu0 < 0 ? 0.0 : cpu_s() - cpu0) << "\n";
  for (std::size_t k = 0; k < seen.ms.size(); ++k) f << seen.seq[k] << " " << seen.ms[k] << "\n";
  return f ? 0 : 1;
}

}  // namespace

int read_large(const std::string& role, const std::string& impl, int domain, int count, const std::string& out,
               std::int64_t end, const runtime::Network& network) {
  return role == "mesh" ? large_reader<DeformedMesh>(impl, domain, count, out, end, network)
                        : large_reader<CameraFrame>(impl, domain, count, out, end, network);
}

namespace {

// ---- between hosts

// Appends `bare` and `ours` (with its ratios) to `rows` as rows `name`
// over `hosts` hosts.
void between_hosts(std::vector<Row>& rows, const char* name, int hosts, Row bare, Row ours) {
  add_ratios(ours, bare);
  for (Row* r : {&bare, &ours}) {
    r->name = name;
    r->params.push_back({"hosts", double(hosts)});
    rows.push_back(std::move(*r));
  }
}

// The same round trips and meshes between hosts made of network namespaces
// (Hosts), over UDP on their bridge: this process's side on host 0 (a
// thread of its own moves there), the round trips' peer on host 1, one
// mesh reader on each of hosts 1 and 2. None where the hosts cannot be
// made here; the progress line says why.
std::vector<Row> hosts_rows(const Context& c, double seconds, int count, int rounds) {
  std::string why;
  const std::unique_ptr<Hosts> hosts = Hosts::make(c.domain, 3, c.work / "dds_hosts", why);
  if (!hosts) {
    progress("dds between hosts: skipped: " + why);
    return {};
  }
  std::vector<Row> rows;
  std::exception_ptr error;
  std::thread([&] {
    try {
      hosts->enter(0);
      const std::string s = std::to_string(int(seconds));
      progress("dds rtt_hosts bare Fast DDS, " + s + " s at 1 kHz, " + hosts->address(0) + " to " + hosts->address(1));
      const pid_t bare_peer = start_peer("bare", c.domain, seconds, 0, hosts->exec(1));
      Row bare = rtt_row("bare", bare_ping(c.domain, seconds));
      stop(bare_peer);
      progress("dds rtt_hosts hcosim runtime, " + s + " s at 1 kHz, " + hosts->address(0) + " to " + hosts->address(1));
      between_hosts(rows, "rtt_hosts", 2, std::move(bare),
                    rtt_row("hcosim", hcosim_rtt(c.domain, seconds, hosts.get())));
      const int vertices = 100000, readers = 2;
      MeshTotals bare_t, ours_t;
      for (int round = 0; round < rounds; ++round)
        for (const bool first : {true, false}) {
          const bool is_bare = first == (round % 2 == 0);
          const std::string impl = is_bare ? "bare" : "hcosim";
          progress("dds mesh_hosts " + impl + ": " + std::to_string(vertices) + " vertices from " + hosts->address(0) +
                   " to " + hosts->address(1) + " and " + hosts->address(2) + ", round " + std::to_string(round + 1) +
                   " of " + std::to_string(rounds) + ", " + std::to_string(count) + " samples at 60 Hz");
          large_round<DeformedMesh>(c, impl, vertices, readers, count, round, is_bare ? bare_t : ours_t, hosts.get());
        }
      between_hosts(rows, "mesh_hosts", 3, mesh_row("bare", vertices, readers, bare_t),
                    mesh_row("hcosim", vertices, readers, ours_t));
      // A camera's frames to the AR view on another host, as many as meshes.
      MeshTotals bare_f, ours_f;
      for (int round = 0; round < rounds; ++round)
        for (const bool first : {true, false}) {
          const bool is_bare = first == (round % 2 == 0);
          const std::string impl = is_bare ? "bare" : "hcosim";
          progress("dds frame_hosts " + impl + ": 640x480 bgr8 frames from " + hosts->address(0) + " to " +
                   hosts->address(1) + ", round " + std::to_string(round + 1) + " of " + std::to_string(rounds) + ", " +
                   std::to_string(count) + " frames at 30 Hz");
          large_round<CameraFrame>(c, impl, 0, 1, count, round, is_bare ? bare_f : ours_f, hosts.get());
        }
      between_hosts(rows, "frame_hosts", 2, frame_row("bare", 1, bare_f), frame_row("hcosim", 1, ours_f));
    } catch (...) {
      error = std::current_exception();
    }
  }).join();
  if (error) std::rethrow_exception(error);
  return rows;
}

// One host's rows, then the rows between hosts.
std::vector<Row> all_rows(const Context& c) {
  std::vector<Row> rows = dds_rows(c);
  for (Row& r : hosts_rows(c, c.quick ? 5 : 30, c.quick ? 60 : 200, c.quick ? 2 : 6)) rows.push_back(std::move(r));
  return rows;
}

}  // namespace

Suite dds_suite() {
  Suite s{"dds",
          "the DDS transport between processes: 1 kHz haptic round trips and 60 Hz deformed meshes, hcosim's runtime "
          "against bare Fast DDS in the same run, on one host and between hosts made of network namespaces",
          all_rows};
  s.tables = {{"rtt",
               "HapticState written at 1 kHz, answered at once by a ForceFeedback from another process; time from "
               "write to the answer's take, pooled over every tick, hcosim's runtime on both ends against Fast DDS "
               "alone (BEST_EFFORT, KEEP_LAST 1)."},
              {"mesh_pub",
               "DeformedMesh (24 bytes a vertex) written at 60 Hz to 1 or 3 reader processes, RELIABLE; latency from "
               "write to take pooled over readers; cpu_pct is the writer's and readers' processes together, % of one "
               "core; hcosim's runtime (with sample validation) against a bare Fast DDS writer and readers of the "
               "same bytes, transports and QoS, in alternating rounds; p99_split_ratio is one impl's p99 over its odd "
               "rounds against its even ones, how far two p99s of the same thing fall apart on this machine."}};
  s.plots = {{"mesh_pub",
              "vertices",
              "p99_ms",
              "vertices per mesh",
              "p99 latency (ms)",
              {"impl", "subscribers"},
              {},
              {"impl", "bare"}},
             {"mesh_pub",
              "vertices",
              "cpu_pct",
              "vertices per mesh",
              "CPU (% of one core)",
              {"impl", "subscribers"},
              {},
              {"impl", "bare"}}};
  s.tables.push_back({"rtt_hosts",
                      "The rtt rows' round trips between two hosts made of Linux network namespaces on one bridge "
                      "(each its own address and /dev/shm: UDP only), this process's side on one, the peer on the "
                      "other."});
  s.tables.push_back({"mesh_hosts",
                      "The mesh_pub rows' 10^5-vertex meshes between hosts made of network namespaces: written on "
                      "one, read by one process on each of two others, over UDP (fragments of 64 KB datagrams), "
                      "RELIABLE; alternating rounds as above."});
  s.tables.push_back({"frame_hosts",
                      "A camera's 640x480 bgr8 CameraFrames (921,600 bytes of pixels) at 30 Hz between hosts made of "
                      "network namespaces: written on one, read by one process on another (the AR view's place), "
                      "over UDP, RELIABLE; alternating rounds as above."});
  // Bare Fast DDS's own losses are the baseline's, reported beside ours.
  s.goals = {
      {"no sample lost with reliable QoS", "mesh_pub", "loss_ratio", 0, "impl", "hcosim"},
      {"hcosim's p99 within 1.2 times bare Fast DDS's", "mesh_pub", "p99_ratio_to_bare", 1.2, "impl", "hcosim"},
      {"between hosts, the haptic round trip's p99 within 1.5 times bare Fast DDS's", "rtt_hosts", "p99_ratio_to_bare",
       1.5, "impl", "hcosim"},
      {"between hosts, no mesh lost with reliable QoS", "mesh_hosts", "loss_ratio", 0, "impl", "hcosim"},
      {"between hosts, hcosim's mesh p99 within 1.2 times bare Fast DDS's", "mesh_hosts", "p99_ratio_to_bare", 1.2,
       "impl", "hcosim"},
      {"between hosts, no camera frame lost with reliable QoS", "frame_hosts", "loss_ratio", 0, "impl", "hcosim"},
      {"between hosts, hcosim's frame p99 within 1.2 times bare Fast DDS's", "frame_hosts", "p99_ratio_to_bare", 1.2,
       "impl", "hcosim"}};
  return s;
}

}  // namespace hcosim::services::bench
