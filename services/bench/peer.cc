#include "services/bench/peer.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <thread>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include "adapters/deployment.h"
#include "services/bench/bench.h"
#include "services/bench/harness.h"
#include "services/runtime/endpoint.h"
#include "services/runtime/service.h"

namespace hcosim::services::bench {

using namespace eprosima::fastdds::dds;

DomainParticipant* bare_participant(int domain, bool mesh_transports, const runtime::Network& network) {
  DomainParticipantQos q;  // constructed, not PARTICIPANT_QOS_DEFAULT: no XML profile applies
  if (mesh_transports) {
    auto shm = std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>();
    shm->segment_size(8 * 1024 * 1024);
    shm->port_queue_capacity(1024);
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    if (network.socket_buffer_bytes > 0)
      udp->sendBufferSize = udp->receiveBufferSize = std::uint32_t(network.socket_buffer_bytes);
    if (!network.address.empty()) udp->interfaceWhiteList = {network.address};
    q.transport().use_builtin_transports = false;
    q.transport().user_transports = {shm, udp};
  }
  DomainParticipant* p = DomainParticipantFactory::get_instance()->create_participant(domain, q);
  if (!p) throw std::runtime_error("bench: Fast DDS cannot create a participant on domain " + std::to_string(domain));
  return p;
}

void destroy_bare(DomainParticipant* p) {
  p->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(p);
}

void await_match(const std::function<int()>& writers_readers, int want) {
  const std::int64_t deadline = runtime::mono_ns() + 10'000'000'000;
  while (writers_readers() < want && runtime::mono_ns() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

namespace {

// Round trips: BEST_EFFORT and KEEP_LAST 1 set in code, default transports.
struct Bare {
  DomainParticipant* participant;
  DataWriter* writer;
  DataReader* reader;

  template <class Out, class In>
  static Bare make(int domain, const char* out_topic, const char* in_topic) {
    Bare b;
    b.participant = bare_participant(domain, false);
    DataWriterQos wq = DATAWRITER_QOS_DEFAULT;
    wq.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
    wq.history().kind = KEEP_LAST_HISTORY_QOS;
    wq.history().depth = 1;
    DataReaderQos rq = DATAREADER_QOS_DEFAULT;
    rq.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
    rq.history().kind = KEEP_LAST_HISTORY_QOS;
    rq.history().depth = 1;
    b.writer = b.participant->create_publisher(PUBLISHER_QOS_DEFAULT)
                   ->create_datawriter(bare_topic<Out>(b.participant, out_topic), wq);
    b.reader = b.participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT)
                   ->create_datareader(bare_topic<In>(b.participant, in_topic), rq);
    return b;
  }
};

// ---- the peer's side of the round trips

// The far end's endpoints: hcosim's runtime, or Fast DDS with nothing of ours.
struct Pong {
  std::function<bool()> wait;  // an unread HapticState is there
  std::function<bool(HapticState&)> take;
  std::function<void(ForceFeedback&)> write;
};

const eprosima::fastrtps::Duration_t kWait = runtime::to_dds(std::chrono::milliseconds(100));

int pong_loop(Pong& p, std::int64_t end) {
  HapticState in;
  ForceFeedback out;
  out.source("bench");
  while (!runtime::stop_requested() && runtime::mono_ns() < end) {
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

}  // namespace

pid_t start_peer(const std::string& impl, int domain, double seconds, int priority, const std::vector<std::string>& on,
                 const std::vector<std::string>& args) {
  std::vector<std::string> all = {"bench-peer",
                                  "--impl",
                                  impl,
                                  "--domain",
                                  std::to_string(domain),
                                  "--duration",
                                  std::to_string(seconds + 30),
                                  "--priority",
                                  std::to_string(priority)};
  all.insert(all.end(), args.begin(), args.end());
  return start_self(on, all);
}

Rtt bare_ping(int domain, double seconds) {
  Bare b = Bare::make<HapticState, ForceFeedback>(domain, "HapticState", "ForceFeedback");
  await_match(
      [&] {
        PublicationMatchedStatus pm;
        SubscriptionMatchedStatus sm;
        b.writer->get_publication_matched_status(pm);
        b.reader->get_subscription_matched_status(sm);
        return std::min(pm.current_count, sm.current_count);
      },
      1);
  ForceFeedback f;
  SampleInfo info;
  Rtt r = ping(
      seconds, [&] { return b.reader->wait_for_unread_message(runtime::to_dds(std::chrono::milliseconds(10))); },
      [&](std::uint64_t k) {
        bool hit = false;
        while (b.reader->take_next_sample(&f, &info) == ReturnCode_t::RETCODE_OK)
          hit = hit || (info.valid_data && f.answers_seq() == k);
        return hit;
      },
      [&](HapticState& s) { b.writer->write(&s); });
  destroy_bare(b.participant);
  return r;
}

Rtt bare_rtt(int domain, double seconds, int priority) {
  const pid_t peer = start_peer("bare", domain, seconds, priority);
  // On a thread of its own, so that the scheduling (inherited by the
  // participant's threads, made on it) leaves the bench's others alone.
  Rtt r;
  std::thread([&] {
    runtime::apply({priority, -1});
    r = bare_ping(domain, seconds);
  }).join();
  stop(peer);
  return r;
}

namespace {

struct PeerOptions {
  std::string impl, role = "pong", out = "mesh_reader.txt";
  std::string deployment, host;  // hcosim: the rig's file and this peer's host in it
  int domain = 0, priority = 0, count = 0;
  double duration_s = 60;
};

int peer(const PeerOptions& o) {
  const int domain = o.domain;
  // Before any participant, so that Fast DDS's threads get it too.
  runtime::apply({o.priority, -1});
  const std::int64_t end = runtime::mono_ns() + std::int64_t(o.duration_s * 1e9);
  const std::string& impl = o.impl;
  runtime::install_stop_handlers();
  if (o.role == "mesh" || o.role == "frame") {
    const runtime::Network network = o.deployment.empty()
                                         ? runtime::Network{}
                                         : runtime::network_of(adapters::load_deployment(o.deployment), o.host);
    return read_large(o.role, impl, domain, o.count, o.out, end, network);
  }
  if (o.role == "ping") {
    // The bare pair as a baseline beside a test's deployment, same time, same load.
    const Rtt r = bare_rtt(domain, o.duration_s, o.priority);
    std::printf("{\"sent\": %llu, \"lost\": %llu, \"p50_us\": %.1f, \"p99_us\": %.1f, \"within_0_8ms_ratio\": %.6f}\n",
                (unsigned long long)r.sent, (unsigned long long)r.lost, r.us.percentile(0.5), r.us.percentile(0.99),
                r.sent ? double(r.us.count_at_most(800)) / double(r.sent) : 0.0);
    return r.sent > 0 ? 0 : 1;
  }
  if (impl == "bare") {
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
    destroy_bare(b.participant);
    return code;
  }
  runtime::Options service;
  service.name = "bench_peer";
  service.domain = domain;
  service.rate_hz = 1000;
  service.step_s = 0.001;
  service.qos_file = runtime::default_qos_file();
  service.deployment = o.deployment;
  service.host = o.host;
  runtime::Service svc(service);
  runtime::Reader<HapticState> r = svc.reader<HapticState>();
  runtime::Writer<ForceFeedback> w = svc.writer<ForceFeedback>();
  Pong p{[&] { return r.wait(std::chrono::milliseconds(100)); },
         [&](HapticState& s) {
           bool got = false;
           r.take([&](const HapticState& x) { s = x, got = true; });
           return got;
         },
         [&](ForceFeedback& f) { w.write(f); }};
  return pong_loop(p, end);
}

}  // namespace

void add_peer(CLI::App& app, runtime::Command& chosen) {
  auto o = std::make_shared<PeerOptions>();
  CLI::App* c = app.add_subcommand("bench-peer", "the far end of the dds suite's round trips")->group("");
  c->add_option("--impl", o->impl, "bare Fast DDS or hcosim's endpoints")
      ->required()
      ->check(CLI::IsMember({"bare", "hcosim"}));
  c->add_option("--role", o->role,
                "answer round trips (pong), read meshes (mesh) or camera frames (frame), or ping a bare pong of its "
                "own and print the round trips as JSON (ping, bare only: a test's same-run baseline)")
      ->check(CLI::IsMember({"pong", "mesh", "frame", "ping"}));
  runtime::add_domain(*c, o->domain);
  c->add_option("--duration", o->duration_s, "run time, s")->check(runtime::within(0, 1e6));
  c->add_option("--count", o->count, "meshes or frames to read")->check(CLI::Range(0, 1000000000));
  c->add_option("--out", o->out, "what the mesh reader saw");
  c->add_option("--priority", o->priority, "SCHED_FIFO priority (0: normal)")->check(CLI::Range(0, 99));
  c->add_option("--deployment", o->deployment, "hcosim: a rig's file, whose network section the peer uses")
      ->check(CLI::ExistingFile);
  c->add_option("--host", o->host, "hcosim: the peer's host in that file")->needs("--deployment");
  c->callback([&chosen, o] { chosen = [o] { return peer(*o); }; });
}

}  // namespace hcosim::services::bench
