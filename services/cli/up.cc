// hcosim up: start a deployment's services as processes (the supervisor),
// watch them (the watcher), stop them.
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>

#include <fastdds/dds/domain/DomainParticipantListener.hpp>

#include "adapters/validate.h"
#include "services/cli/cli.h"
#include "services/cli/supervisor.h"
#include "services/cli/watcher.h"
#include "services/foxglove/panels.h"
#include "services/recording/recording.h"
#include "services/runtime/participant.h"
#include "services/runtime/recordings.h"
#include "services/runtime/service.h"

namespace fs = std::filesystem;

namespace hcosim::services::cli {
namespace {

volatile std::sig_atomic_t g_signal = 0;
void on_signal(int s) { g_signal = s; }

// Tells the watcher each participant discovered on the domain: a
// service's participant carries the service's name.
class Discovered : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  explicit Discovered(Watcher& w) : watcher_(w) {}
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
    std::ostringstream where;
    where << info.info.m_guid.guidPrefix << ", discovery at";
    for (const auto& l : info.info.metatraffic_locators.unicast) where << ' ' << l;
    where << ", data at";
    for (const auto& l : info.info.default_locators.unicast) where << ' ' << l;
    watcher_.joined(info.info.m_participantName.to_string(), where.str());
  }

 private:
  Watcher& watcher_;
};

void say(const std::string& text) {
  if (text.empty()) return;
  std::fputs(text.c_str(), stdout);
  std::fflush(stdout);
}

// What `hcosim up` was asked: the file and what the command line overrides.
struct UpOptions {
  std::string file;
  double duration_s = NAN;  // NaN: the file's
  std::string mode;         // "": the file's
  std::string out = "out";
  std::string record;
  std::string host;  // "": every service, here
};

// The command line every service gets: its name, the deployment and the
// time it runs in.
std::vector<std::string> service_args(const adapters::Deployment& d, const UpOptions& o, const std::string& name,
                                      double rate) {
  std::ostringstream r, s;
  r.precision(17);
  s.precision(17);
  r << rate;
  s << d.step_s;
  std::vector<std::string> args{"--name",       name,
                                "--domain",     std::to_string(d.domain),
                                "--mode",       adapters::to_string(d.mode),
                                "--rate",       r.str(),
                                "--step",       s.str(),
                                "--deployment", fs::absolute(d.file).string(),
                                "--out",        fs::absolute(o.out).string()};
  if (!o.host.empty()) args.insert(args.end(), {"--host", o.host});
  return args;
}

// The processes this hcosim up starts: the services of its host (every
// one without --host) that the scene needs, and the lockstep clock where
// the file puts it. Throws a ConfigError when that is nothing.
std::vector<Child> children_of(const adapters::Deployment& d, const UpOptions& o) {
  std::vector<const adapters::ServiceSpec*> mine;
  if (o.host.empty())
    for (const auto& s : d.services) mine.push_back(&s);
  else
    mine = adapters::services_on(d, o.host);
  std::vector<Child> children;
  for (const adapters::ServiceSpec* sp : mine) {
    const adapters::ServiceSpec& s = *sp;
    if (!s.unneeded.empty()) {
      std::printf("hcosim up: not starting %s: %s\n", s.name.c_str(), s.unneeded.c_str());
      continue;
    }
    adapters::check_policy(s, d.mode);  // --mode may have changed the file's mode
    Child c{s.name, find_service(s.kind, d.file, s.line), service_args(d, o, s.name, s.rate_hz), s.on_failure};
    c.observer = adapters::observes(s);
    c.args.insert(c.args.end(), {"--priority", std::to_string(s.priority), "--cpu", std::to_string(s.cpu)});
    children.push_back(std::move(c));
  }
  // Nothing to run is a mistake in the file; the clock alone steps
  // nothing but on its host of several (--host).
  const bool runs_clock = d.mode == adapters::Mode::kLockstep && (o.host.empty() || o.host == d.clock_host);
  if (children.empty() && !(runs_clock && !o.host.empty()))
    throw adapters::ConfigError(d.services_where + ": nothing to run" + (o.host.empty() ? "" : " on host " + o.host) +
                                ": " +
                                (d.services.empty() ? std::string("the deployment lists no services")
                                 : mine.empty()     ? "no service says host: " + o.host
                                                    : "the scene needs none of its services (above)"));
  if (runs_clock) {
    Child clock{"clock", find_service("clock", d.file, 1), service_args(d, o, "clock", 1.0 / d.step_s)};
    std::ostringstream dur;
    dur.precision(17);
    dur << d.duration_s;
    clock.args.insert(clock.args.end(), {"--duration", dur.str()});
    children.push_back(std::move(clock));
  }
  return children;
}

// Every process's credentials, before any starts (docs/security.md).
void check_credentials(const adapters::Deployment& d, const runtime::Security& security,
                       const std::vector<Child>& children) {
  if (!security.on()) return;
  try {
    runtime::check_credentials(security);
    for (const auto& c : children) runtime::check_credentials({d.security, c.name});
  } catch (const std::runtime_error& e) {
    throw adapters::ConfigError(d.security_where + ": " + e.what());
  }
}

// A domain whose UDP ports another program's socket may take.
void warn_of_ephemeral_ports(int domain) {
  if (const auto [lo, hi] = runtime::ephemeral_ports(); runtime::in_ephemeral_range(domain, lo, hi))
    std::printf(
        "hcosim up: warning: domain %d's UDP ports (%d to %d) lie in this machine's ephemeral port range (%d to %d, "
        "/proc/sys/net/ipv4/ip_local_port_range): another program's socket can take one and keep the services from "
        "finding each other; choose a domain whose ports lie outside it (docs/deployment.md)\n",
        domain, runtime::first_port(domain), runtime::last_port(domain), lo, hi);
}

// The services the watcher waits for. With --host it hears the whole rig:
// every host's services join and run before this host's duration counts,
// and one never heard (its host down, or discovery that cannot cross the
// network) is named.
std::vector<std::string> watched(const adapters::Deployment& d, const UpOptions& o,
                                 const std::vector<Child>& children) {
  std::vector<std::string> names;
  if (o.host.empty()) {
    for (const auto& c : children) names.push_back(c.name);
    return names;
  }
  for (const auto& s : d.services)
    if (s.unneeded.empty()) names.push_back(s.name);
  if (d.mode == adapters::Mode::kLockstep) names.push_back("clock");
  return names;
}

// How many hcosim ups this run has, one a host that runs something: a
// lockstep follower hears them all before its first step, to know every
// recording (runtime/recordings.h).
std::size_t ups_of(const adapters::Deployment& d, const UpOptions& o) {
  if (o.host.empty()) return 1;
  std::set<std::string> hosts;
  for (const auto& s : d.services)
    if (s.unneeded.empty()) hosts.insert(s.host);
  if (d.mode == adapters::Mode::kLockstep) hosts.insert(d.clock_host);
  return hosts.size();
}

// Runs until a child that exits ends the run (lockstep: the clock exiting
// 0 is the normal end) unless its on_failure policy says otherwise, the
// duration, or Ctrl-C; returns why it ended. A real-time run's duration
// counts from when every service runs its loop (one may first build its
// model for seconds), or from Watcher::kStartWaitS if one never says so.
std::string watch(const adapters::Deployment& d, Supervisor& supervisor, Watcher& watcher,
                  runtime::Reader<ServiceStatus>& status, std::int64_t start) {
  const bool timed = d.mode == adapters::Mode::kRealtime && d.duration_s > 0;
  std::int64_t end = INT64_MAX;
  std::string reason;
  const auto ran = [&](const std::string& name) { return watcher.running(name); };
  while (reason.empty()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    status.take([&](const ServiceStatus& s) { watcher.status(s); });
    const bool was_started = watcher.started();
    say(watcher.update((runtime::mono_ns() - start) * 1e-9, runtime::mono_ns()));
    if (timed && !was_started && watcher.started()) end = runtime::mono_ns() + std::int64_t(d.duration_s * 1e9);
    std::string said;
    if (g_signal)
      reason = std::string("stopped by ") + (g_signal == SIGINT ? "SIGINT" : "SIGTERM");
    else if (runtime::mono_ns() >= end)
      reason = "duration reached";
    else
      reason = supervisor.poll(ran, said);
    if (!said.empty()) say(watcher.finish() + said);
  }
  say(watcher.finish());
  return reason;
}

// Closes the recording and says what it holds and what it lost.
void close_recording(recording::Recorder& recorder, const std::string& path) {
  recorder.close();
  std::printf("hcosim up: recorded %llu samples to %s", static_cast<unsigned long long>(recorder.samples()),
              path.c_str());
  if (const std::uint64_t n = recorder.derived())
    std::printf(", and %llu scene messages for Foxglove", static_cast<unsigned long long>(n));
  std::printf("\n");
  if (const std::string lost = recorder.losses(); !lost.empty())
    std::printf("hcosim up: samples Fast DDS reports the recording never received: %s\n", lost.c_str());
  if (const std::string dropped = recorder.dropped(); !dropped.empty())
    std::printf("hcosim up: samples dropped because the recording's file fell %zu MiB behind: %s\n",
                recording::Recorder::kQueueBytes >> 20, dropped.c_str());
}

int up(const UpOptions& o) {
  adapters::Deployment d = adapters::load_deployment(o.file);
  if (!o.mode.empty()) d.mode = adapters::parse_mode(o.mode);
  if (!std::isnan(o.duration_s)) d.duration_s = o.duration_s;
  if (d.mode == adapters::Mode::kLockstep && d.duration_s == 0)
    throw std::invalid_argument("lockstep needs a duration (in the file or --duration)");
  const fs::path out = o.out;
  const fs::path logs = out / "logs";
  fs::create_directories(logs);
  std::vector<Child> children = children_of(d, o);
  const runtime::Security security{d.security, runtime::kToolIdentity};
  check_credentials(d, security, children);

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  std::printf("hcosim up: %s, domain %d, %s, %zu service(s)%s%s%s\n", d.file.c_str(), d.domain,
              adapters::to_string(d.mode), children.size(), o.host.empty() ? "" : (" on host " + o.host).c_str(),
              d.duration_s > 0 ? "" : ", until Ctrl-C",
              security.on() ? (", DDS Security on (" + d.security + ")").c_str() : "");
  warn_of_ephemeral_ports(d.domain);
  // The host of a discovery server runs it beside its services, until the
  // end; no one waits for it. fast-discovery-server itself, not `fastdds
  // discovery`, whose Python wrapper leaves the server running when stopped.
  const runtime::Network network = runtime::network_of(d, o.host);
  if (network.discovery == "server" && o.host == d.network.server) {
    Child server{"discovery",
                 find_program("fast-discovery-server", "the Discovery Server (Debian package fastdds-tools)"),
                 {"-i", "0", "-l", network.server, "-p", std::to_string(network.server_port)}};
    server.observer = true;
    children.insert(children.begin(), std::move(server));
  }
  Watcher watcher(watched(d, o, children), d.domain, isatty(STDOUT_FILENO));
  Discovered discovered(watcher);
  // up's participant exists before the services, so that the recorder's
  // readers are there when their writers appear. Owned, so that it is gone
  // before the shared-memory clean at the end: a dead process's ports that
  // it holds open would stay behind.
  // Recording, it says so by its name: lockstep followers wait for their
  // writers to reach it before their first step (runtime/recordings.h).
  const char* participant_name = o.record.empty() ? runtime::kUpParticipant : runtime::kRecordingParticipant;
  auto participant = std::make_unique<runtime::Participant>(d.domain, participant_name, runtime::default_qos_file(),
                                                            &discovered, false, security, network);
  // In lockstep the recorder's readers are reliable: the services wait for
  // them too, so a recording holds every sample.
  participant->set_lockstep(d.mode == adapters::Mode::kLockstep);
  auto status = std::make_unique<runtime::Reader<ServiceStatus>>(
      *participant, [](const ServiceStatus& s) { return adapters::validate(s); });
  std::unique_ptr<recording::Recorder> recorder;
  if (!o.record.empty()) {
    adapters::foxglove::Options scene;
    scene.tag_id = d.scene.marker.id.value_or(scene.tag_id);
    recorder = std::make_unique<recording::Recorder>(*participant, o.record, std::vector<std::string>{},
                                                     recording::format_of(o.record), recording::McapCompression::zstd,
                                                     foxglove::panel_channels(foxglove::panel_items(d), scene));
  }
  setenv("HCOSIM_UPS", std::to_string(ups_of(d, o)).c_str(), 1);
  Supervisor supervisor(logs, d.mode);
  for (const Child& c : children)
    std::printf("  started %-16s pid %-7d %s\n", c.name.c_str(), int(supervisor.start(c)), c.exe.c_str());
  std::fflush(stdout);

  const std::int64_t start = runtime::mono_ns();
  const std::string reason = watch(d, supervisor, watcher, *status, start);
  supervisor.stop();
  if (recorder) close_recording(*recorder, o.record);
  recorder.reset();
  status.reset();
  participant.reset();
  supervisor.clean(d.domain);

  std::printf("hcosim up: %s after %.1f s\n%s", reason.c_str(), (runtime::mono_ns() - start) * 1e-9,
              supervisor.last_words().c_str());
  for (const auto& c : supervisor.children())
    std::printf("  %-16s %-32s log %s\n", c.name.c_str(),
                (describe(c.status) + (c.restarts ? ", " + std::to_string(c.restarts) + " restarts" : "")).c_str(),
                supervisor.log_of(c.name).c_str());
  std::printf("outputs: %s\n", fs::absolute(out).c_str());
  return supervisor.code();
}

}  // namespace

void add_up(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<UpOptions>();
  CLI::App* c = app.add_subcommand("up",
                                   "start the services of a deployment file, each in its own process, and stop them "
                                   "all at the end, on Ctrl-C, or when one fails; with --record, record every topic "
                                   "of the run");
  c->add_option("FILE", o->file, "deployment file (docs/deployment.md)")->required();
  c->add_option("--duration", o->duration_s, "run time, s (default: the file's; 0: until Ctrl-C, real time only)")
      ->option_text("S")
      ->check(runtime::within(0, 1e9));
  c->add_option("--mode", o->mode, "time: wall clock, or the lockstep clock (default: the file's)")
      ->option_text("realtime|lockstep")
      ->check(CLI::IsMember({"realtime", "lockstep"}).description(""));
  c->add_option("--out", o->out, "folder for logs and the services' outputs (default: out)")->option_text("DIR");
  c->add_option("--host", o->host,
                "start only the services the file places on host NAME (and the lockstep clock if it is there); "
                "each host of the rig runs its own hcosim up with the same file (docs/deployment.md)")
      ->option_text("NAME");
  c->add_option("--record", o->record,
                "record every topic of the run into REC, MCAP for a name ending in .mcap (docs/recording.md)")
      ->option_text("REC");
  c->callback([&chosen, o] { chosen = [o] { return up(*o); }; });
}

}  // namespace hcosim::services::cli
