// Typed DataWriter and DataReader over the participant's QoS profiles.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "services/runtime/participant.h"

namespace hcosim::services::runtime {

// A std::chrono duration as Fast DDS's Duration_t.
inline eprosima::fastrtps::Duration_t to_dds(std::chrono::nanoseconds d) {
  const auto s = std::chrono::duration_cast<std::chrono::seconds>(d);
  return eprosima::fastrtps::Duration_t(static_cast<int32_t>(s.count()), static_cast<uint32_t>((d - s).count()));
}

// Heartbeat period of lockstep writers, ns (see Writer).
inline constexpr std::uint32_t kLockstepHeartbeatNs = 1'000'000;
// In lockstep HapticState's writers and readers are TRANSIENT_LOCAL: a
// step of the Gauss-Seidel group waits for the device's state of that same
// step, which a reader matched a moment after the write must still get
// (KEEP_LAST 1 keeps it). The answers cannot be so: with several instances
// (one per object) Fast DDS 2.9.1 slowed a lockstep run thirtyfold; a
// source waits for its writer to reach the device instead (Writer::reaches).
template <class T>
constexpr bool durable_in_lockstep() {
  return std::is_same_v<T, HapticState>;
}

// In lockstep the step protocol's writers (ClockTick, StepDone) are TRANSIENT_LOCAL
// too, though their readers are not. A VOLATILE reliable writer removes
// each sample once every reader has acknowledged it, and Fast DDS 2.9.1
// seems at times to skip one; the history kept that short, KEEP_LAST never
// pushes the skipped one out, and every heartbeat then carries a GAP from it to the
// newest sample, which each reader walks one sequence number at a time: a
// lockstep run between hosts crawled (docs/cosimulation.md, "A crawl";
// ClockTick's writer in a packet capture). A TRANSIENT_LOCAL writer keeps
// its last samples, in order. Only for writers whose instances are written
// at one rate: a body asleep, published once a second, would leave holes
// between its samples as wide as that.
template <class T>
constexpr bool kept_in_lockstep() {
  return std::is_same_v<T, ClockTick> || std::is_same_v<T, StepDone>;
}

// Heartbeat period of paced writers (see Writer::caught_up).
inline constexpr std::chrono::milliseconds kPacedHeartbeat{20};

// Large samples: with the network's bulk cap (network.h, kBulkFlow) their
// writers send through its flow controller.
template <class T>
constexpr bool bulk() {
  return std::is_same_v<T, DeformedMesh> || std::is_same_v<T, CameraFrame>;
}

// The participant of an endpoint, from its handle (the endpoint's GUID).
inline eprosima::fastrtps::rtps::GuidPrefix_t participant_of(const eprosima::fastrtps::rtps::InstanceHandle_t& h) {
  return eprosima::fastrtps::rtps::iHandle2GUID(h).guidPrefix;
}

// Samples refused by validation: how many and the latest reason. Readers
// on several threads (a haptic thread's and the loop's) add to one.
struct Rejections {
  void add(std::string reason) {
    std::lock_guard<std::mutex> l(m);
    ++count, last = std::move(reason);
  }
  mutable std::mutex m;
  std::uint64_t count = 0;
  std::string last;  // "Topic: reason"
};

// The readers a writer has matched (Fast DDS 2.9.1 leaves
// get_matched_subscriptions unimplemented), kept from its match events.
struct Matches : eprosima::fastdds::dds::DataWriterListener {
  void on_publication_matched(eprosima::fastdds::dds::DataWriter*,
                              const eprosima::fastdds::dds::PublicationMatchedStatus& s) override {
    std::lock_guard<std::mutex> l(m);
    if (s.current_count_change > 0)
      readers.push_back(s.last_subscription_handle);
    else
      readers.erase(std::remove(readers.begin(), readers.end(), s.last_subscription_handle), readers.end());
  }
  mutable std::mutex m;
  std::vector<eprosima::fastrtps::rtps::InstanceHandle_t> readers;
};

namespace detail {
inline thread_local int writes_running = 0;  // writing()
}  // namespace detail

// Whether this thread is inside a Writer's write: Fast DDS hands a sample
// to a reader in the same process on the writer's thread, inside write.
inline bool writing() { return detail::writes_running > 0; }

// Writes samples of T on TopicOf<T>::name with a named QoS profile.
template <class T>
class Writer {
 public:
  explicit Writer(Participant& p, const std::string& profile = TopicOf<T>::qos)
      : p_(p), paced_(bulk<T>() && !p.lockstep() && has_bulk_flow(p)) {
    if (p.lockstep()) {
      eprosima::fastdds::dds::DataWriterQos qos;
      p.publisher()->get_datawriter_qos_from_profile(profile, qos);
      qos.reliability().kind = eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
      // Every step waits for its outputs' acknowledgments, which readers
      // send in answer to a heartbeat: the default 3 s period would make
      // each step last that long.
      qos.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, kLockstepHeartbeatNs);
      if (durable_in_lockstep<T>() || kept_in_lockstep<T>())
        qos.durability().kind = eprosima::fastdds::dds::TRANSIENT_LOCAL_DURABILITY_QOS;
      writer_ = p.publisher()->create_datawriter(p.topic<T>(), qos, &matches_, match_mask());
    } else if (paced_) {
      eprosima::fastdds::dds::DataWriterQos qos;
      p.publisher()->get_datawriter_qos_from_profile(profile, qos);
      qos.publish_mode().kind = eprosima::fastdds::dds::ASYNCHRONOUS_PUBLISH_MODE;
      qos.publish_mode().flow_controller_name = kBulkFlow;
      // Readers acknowledge in answer to a heartbeat; caught_up() learns
      // within this that the link is free (Fast DDS's default is 3 s).
      qos.reliable_writer_qos().times.heartbeatPeriod = to_dds(kPacedHeartbeat);
      writer_ = p.publisher()->create_datawriter(p.topic<T>(), qos, &matches_, match_mask());
    } else {
      writer_ = p.publisher()->create_datawriter_with_profile(p.topic<T>(), profile, &matches_, match_mask());
    }
    if (!writer_)
      throw std::runtime_error(std::string("cannot create a writer for ") + TopicOf<T>::name + " with QoS profile '" +
                               profile + "'");
  }
  ~Writer() { p_.publisher()->delete_datawriter(writer_); }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // False if Fast DDS refused the sample (for example a full reliable history).
  bool write(T& sample) {
    struct Running {
      Running() { ++detail::writes_running; }
      ~Running() { --detail::writes_running; }
    } running;
    return writer_->write(&sample);
  }

  // Blocks until every matched reliable reader acknowledged what was
  // written, or `timeout` passes; true if acknowledged. Call before exiting
  // when the last sample matters: deleting the writer drops unsent samples.
  bool wait_acknowledged(std::chrono::nanoseconds timeout) {
    return writer_->wait_for_acknowledgments(to_dds(timeout)) == ReturnCode_t::RETCODE_OK;
  }

  // Whether write() only queues the sample for the bulk flow controller
  // (realtime, under the network's bulk_mbit).
  bool paced() const { return paced_; }
  // Whether every reliable reader has acknowledged every sample written: a
  // paced writer that has not is still sending an older one, and a newer
  // one would wait behind it.
  bool caught_up() const {
    return writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(0, 0)) == ReturnCode_t::RETCODE_OK;
  }

  // Readers currently matched: zero means an output nobody reads.
  int matched() const {
    eprosima::fastdds::dds::PublicationMatchedStatus s;
    writer_->get_publication_matched_status(s);
    return s.current_count;
  }

  // Whether a reader of the participant that `peer` (any endpoint's
  // handle) belongs to is matched: what is written now reaches it.
  bool reaches(const eprosima::fastrtps::rtps::InstanceHandle_t& peer) const {
    const auto prefix = participant_of(peer);
    std::lock_guard<std::mutex> l(matches_.m);
    return std::any_of(matches_.readers.begin(), matches_.readers.end(),
                       [&](const auto& r) { return participant_of(r) == prefix; });
  }

 private:
  static eprosima::fastdds::dds::StatusMask match_mask() {
    return eprosima::fastdds::dds::StatusMask::publication_matched();
  }
  static bool has_bulk_flow(Participant& p) {
    const auto& flows = p.publisher()->get_participant()->get_qos().flow_controllers();
    return std::any_of(flows.begin(), flows.end(),
                       [](const auto& f) { return f && f->name && std::string(f->name) == kBulkFlow; });
  }
  Participant& p_;
  const bool paced_;
  Matches matches_;  // before writer_, which calls it
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

// Reads samples of T; each one passes `validate` before the caller sees it,
// and refused ones are counted in `rejections` (when given).
// Samples a monitoring reader (a recorder, echo, hz) keeps per instance
// between two takes: 256 ms of a 1 kHz topic, so that one the scheduler
// leaves out for a while under load loses nothing (with the control
// profile's 1, hcosim record --device kept 3392 of 3917 states in a
// parallel ctest run; a starved echo showed no status report in 6 s).
constexpr int kMonitorDepth = 256;

template <class T>
class Reader {
 public:
  using Validator = std::function<std::optional<std::string>(const T&)>;

  // `depth` > 0 keeps that many samples per instance instead of the
  // profile's history: a recorder must not lose a sample it polls late.
  Reader(Participant& p, Validator validate = nullptr, Rejections* rejections = nullptr,
         const std::string& profile = TopicOf<T>::qos, int depth = 0)
      : p_(p), validate_(std::move(validate)), rejections_(rejections) {
    if (p.lockstep() && depth == 0) depth = Participant::kLockstepDepth;
    if (depth > 0) {
      eprosima::fastdds::dds::DataReaderQos qos;
      p.subscriber()->get_datareader_qos_from_profile(profile, qos);
      if (p.lockstep()) {
        qos.reliability().kind = eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS;
        qos.reliable_reader_qos().times.heartbeatResponseDelay = eprosima::fastrtps::Duration_t(0, 0);
        if (durable_in_lockstep<T>()) qos.durability().kind = eprosima::fastdds::dds::TRANSIENT_LOCAL_DURABILITY_QOS;
      }
      qos.history().kind = eprosima::fastdds::dds::KEEP_LAST_HISTORY_QOS;
      qos.history().depth = depth;
      qos.resource_limits().max_instances = 64;
      qos.resource_limits().max_samples_per_instance = depth;
      qos.resource_limits().max_samples = 64 * depth;
      reader_ = p.subscriber()->create_datareader(p.topic<T>(), qos);
    } else {
      reader_ = p.subscriber()->create_datareader_with_profile(p.topic<T>(), profile);
    }
    if (!reader_)
      throw std::runtime_error(std::string("cannot create a reader for ") + TopicOf<T>::name + " with QoS profile '" +
                               profile + "'");
  }
  ~Reader() { p_.subscriber()->delete_datareader(reader_); }

  // Calls f() on Fast DDS's receiving thread each time samples arrive (f
  // takes them), instead of the caller waking a thread of its own: a wake-up
  // less on the way (each is late by tens of microseconds on a virtual
  // machine: the device's wake-up jitter, in its closing line). The receiving
  // threads have the scheduling of the thread that made the participant.
  // on_arrival(nullptr) returns once no call of f is running, and none
  // follows.
  void on_arrival(std::function<void()> f) {
    {
      std::lock_guard<std::mutex> l(arrival_.m);
      arrival_.f = std::move(f);
    }
    reader_->set_listener(arrival_.f ? &arrival_ : nullptr, eprosima::fastdds::dds::StatusMask::data_available());
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  // Takes every unread sample; calls f(sample) for each admissible one, in
  // arrival order. Returns how many were admitted.
  template <class F>
  std::size_t take(F&& f) {
    std::size_t admitted = 0;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader_->take_next_sample(&sample_, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;  // instance disposal, not data
      if (validate_) {
        if (auto problem = validate_(sample_)) {
          if (rejections_) rejections_->add(std::string(TopicOf<T>::name) + ": " + *problem);
          continue;
        }
      }
      ++admitted;
      current_writer_ = info.publication_handle;
      f(sample_);
    }
    return admitted;
  }

  // The writer of the sample being passed to f (valid inside f).
  const eprosima::fastrtps::rtps::InstanceHandle_t& current_writer() const { return current_writer_; }

  // take() for a lockstep step: only samples stamped before `step`, in
  // step order (ties in arrival order); later ones are kept for the steps
  // they belong to.
  template <class F>
  std::size_t take_before(std::uint64_t step, F&& f) {
    take([&](const T& s) { held_.push_back({s, current_writer_}); });
    std::stable_sort(held_.begin(), held_.end(),
                     [](const Held& a, const Held& b) { return a.sample.stamp().step() < b.sample.stamp().step(); });
    std::size_t n = 0;
    for (; n < held_.size() && held_[n].sample.stamp().step() < step; ++n) {
      current_writer_ = held_[n].writer;
      f(held_[n].sample);
    }
    held_.erase(held_.begin(), held_.begin() + std::ptrdiff_t(n));
    return n;
  }

  // Blocks until a sample is unread or `timeout` passes; true if one is.
  bool wait(std::chrono::nanoseconds timeout) { return reader_->wait_for_unread_message(to_dds(timeout)); }

  // Samples Fast DDS reports this reader will never receive (gaps the
  // writer could not repair, or skipped), since it was made.
  std::uint64_t lost() const {
    eprosima::fastdds::dds::SampleLostStatus s;
    reader_->get_sample_lost_status(s);
    return std::uint64_t(s.total_count);
  }

  // Writers currently matched.
  int matched() const {
    eprosima::fastdds::dds::SubscriptionMatchedStatus s;
    reader_->get_subscription_matched_status(s);
    return s.current_count;
  }

 private:
  // Outlives reader_, which may call it until deleted; f is cleared under
  // the same lock it runs under.
  struct Arrival : eprosima::fastdds::dds::DataReaderListener {
    void on_data_available(eprosima::fastdds::dds::DataReader*) override {
      std::lock_guard<std::mutex> l(m);
      if (f) f();
    }
    std::mutex m;
    std::function<void()> f;
  };

  Participant& p_;
  Validator validate_;
  Rejections* rejections_;
  Arrival arrival_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  T sample_;  // reused so that large samples do not reallocate every take
  struct Held {
    T sample;
    eprosima::fastrtps::rtps::InstanceHandle_t writer;
  };
  std::vector<Held> held_;  // lockstep: samples taken ahead of their step
  eprosima::fastrtps::rtps::InstanceHandle_t current_writer_;
};

}  // namespace hcosim::services::runtime
