// Recordings: samples of the topic contract as they were on the wire (CDR),
// each with its topic, step, simulated time and receive time, in one file:
// hcosim's own format, or MCAP (services/recording/mcap.h) with each topic a
// channel and its IDL type the channel's schema. Both in docs/recording.md.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "services/recording/mcap.h"
#include "services/runtime/endpoint.h"
#include "services/runtime/participant.h"
#include "services/runtime/topics.h"

namespace hcosim::services::recording {

struct Record {
  std::string topic;
  std::uint64_t step = 0;         // StepStamp.step (ClockTick, StepDone: their step; topology: 0)
  std::int64_t sim_time_ns = 0;   // StepStamp.sim_time_ns (0 where the type has none)
  std::int64_t receive_ns = 0;    // CLOCK_REALTIME when the recorder took it, ns
  std::int64_t publish_ns = 0;    // StepStamp.wall_time_ns, when it was written (MCAP's publish time; written only)
  std::vector<std::uint8_t> cdr;  // the sample, serialized as on the wire (encapsulation header first)
};

// A message derived from the topics (Foxglove's scene channels,
// adapters/foxglove/panels.h), written to MCAP beside them on its own channel.
struct Derived {
  std::string topic;
  std::string schema_name;        // e.g. "foxglove::SceneUpdate"
  const char* schema_text = "";   // its self-contained OMG IDL
  std::vector<std::uint8_t> cdr;  // encapsulation header first
};
// What a record gives; called on the recorder's writing thread.
using Derive = std::function<std::vector<Derived>(const Record&)>;

enum class RecordingFormat { hcosim, mcap };
// A recording's format from its name: mcap for a name ending in .mcap.
RecordingFormat format_of(const std::string& path);
RecordingFormat parse_recording_format(const std::string& name);  // throws std::invalid_argument
McapCompression parse_compression(const std::string& name);       // zstd, lz4 or none; throws likewise

// The self-contained OMG IDL text of a contract type ("hcosim::DeformedMesh"):
// common.idl and the file that declares it, their #include lines removed.
// Throws std::invalid_argument for a type the contract does not declare.
std::string idl_schema(const std::string& type_name);

// Appends records to a new file. Throws std::runtime_error when the file
// cannot be written, std::invalid_argument for a record of no contract
// topic in MCAP (its channel needs the topic's type).
class RecordingWriter {
 public:
  RecordingWriter(const std::string& path, RecordingFormat format, McapCompression compression = McapCompression::zstd);
  explicit RecordingWriter(const std::string& path) : RecordingWriter(path, format_of(path)) {}
  void write(const Record& r);
  // MCAP only (throws std::invalid_argument otherwise), at the time of the record it comes from.
  void write(const Derived& d, std::int64_t receive_ns, std::int64_t publish_ns);
  void close();  // throws if anything failed to reach the disk
  std::uint64_t count() const { return count_; }

 private:
  std::string path_;
  std::ofstream out_;                                                        // hcosim's format, or
  std::unique_ptr<McapWriter> mcap_;                                         // MCAP's
  std::map<std::string, std::pair<std::uint16_t, std::uint32_t>> channels_;  // MCAP: by topic, channel and sequence
  std::map<std::string, std::uint16_t> schemas_;                             // MCAP: derived channels' schemas by name
  std::uint64_t count_ = 0;

  void write_mcap(std::pair<std::uint16_t, std::uint32_t>& channel, std::int64_t receive_ns, std::int64_t publish_ns,
                  const std::vector<std::uint8_t>& cdr);
};

// Reads records in file order, of either format (told by its first bytes).
// From MCAP, the messages of channels that carry a contract topic in CDR,
// their step and simulated time from the sample's stamp, their receive
// time the log time; other channels are skipped and counted, but for the
// scene channels (schemas foxglove::*), which are derived from the topics. Throws
// std::runtime_error naming the file and byte offset for a file that is
// not a recording or is cut short, and the channel whose schema is not
// its topic's type.
class RecordingReader {
 public:
  explicit RecordingReader(const std::string& path);
  bool next(Record& r);  // false at the end
  std::uint64_t skipped() const { return skipped_; }

 private:
  bool next_mcap(Record& r);

  std::string path_;
  std::ifstream in_;                  // hcosim's format, or
  std::unique_ptr<McapReader> mcap_;  // MCAP's
  std::uint64_t offset_ = 0;
  std::uint64_t skipped_ = 0;
};

// T's type support, made once a thread: its constructor computes the
// type's largest serialized size, a walk through every nested sequence at
// fastddsgen's default bound that cost far more than a sample's own
// serialization (most of a live bridge's CPU, bench foxglove). For
// serializing only: its getKey keeps state between calls (export.cc).
template <class T>
typename runtime::TopicOf<T>::PubSub& type_support() {
  static thread_local typename runtime::TopicOf<T>::PubSub type;
  return type;
}

// A sample of T to and from its CDR bytes.
template <class T>
std::vector<std::uint8_t> to_cdr(const T& sample) {
  auto& type = type_support<T>();
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(const_cast<T*>(&sample))());
  if (!type.serialize(const_cast<T*>(&sample), &payload))
    throw std::runtime_error(std::string("cannot serialize a ") + runtime::TopicOf<T>::name);
  return {payload.data, payload.data + payload.length};
}

// Appends a sample's CDR bytes to `out`: serialised in a buffer this
// thread keeps for T, so that a large sample (a camera frame) costs no
// allocation and one copy.
template <class T>
void append_cdr(const T& sample, std::string& out) {
  auto& type = type_support<T>();
  thread_local eprosima::fastrtps::rtps::SerializedPayload_t payload;
  const std::uint32_t size = type.getSerializedSizeProvider(const_cast<T*>(&sample))();
  if (payload.max_size < size) payload.reserve(size);
  payload.length = 0;
  payload.pos = 0;
  if (!type.serialize(const_cast<T*>(&sample), &payload))
    throw std::runtime_error(std::string("cannot serialize a ") + runtime::TopicOf<T>::name);
  out.append(reinterpret_cast<const char*>(payload.data), payload.length);
}

template <class T>
T from_cdr(const std::vector<std::uint8_t>& bytes) {
  auto& type = type_support<T>();
  eprosima::fastrtps::rtps::SerializedPayload_t payload(std::uint32_t(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = std::uint32_t(bytes.size());
  T sample;
  if (!type.deserialize(&payload, &sample))
    throw std::runtime_error(std::string("a recorded ") + runtime::TopicOf<T>::name + " does not deserialize");
  return sample;
}

namespace detail {
template <class T, class = void>
struct HasStamp : std::false_type {};
template <class T>
struct HasStamp<T, std::void_t<decltype(std::declval<const T&>().stamp())>> : std::true_type {};
template <class T, class = void>
struct HasStep : std::false_type {};
template <class T>
struct HasStep<T, std::void_t<decltype(std::declval<const T&>().step())>> : std::true_type {};
}  // namespace detail

// The record of a sample of T received at `receive_ns`.
template <class T>
Record make_record(const T& s, std::int64_t receive_ns) {
  Record r;
  r.topic = runtime::TopicOf<T>::name;
  if constexpr (detail::HasStamp<T>::value) {
    r.step = s.stamp().step();
    r.sim_time_ns = s.stamp().sim_time_ns();
  } else if constexpr (detail::HasStep<T>::value) {
    r.step = s.step();
  }
  r.receive_ns = receive_ns;
  r.publish_ns = receive_ns;
  if constexpr (detail::HasStamp<T>::value) r.publish_ns = s.stamp().wall_time_ns();
  r.cdr = to_cdr(s);
  return r;
}

// Subscribes to topics of the contract and records every sample: Fast
// DDS's receiving threads take each as it arrives and queue it, and one
// thread of the recorder writes the queue to the file. So a reader's
// history never fills behind a late poll (a burst that a stalled
// recorder's shared-memory port held would overwrite samples there, which
// Fast DDS does not count lost), and a file that stalls (a disk falling
// behind) holds up no receiving thread: while its writer no longer holds
// a sample, a reliable topic's loss could not be repaired.
class Recorder {
 public:
  // `topics` empty: every topic. Throws std::invalid_argument naming an
  // unknown topic, std::runtime_error when the file cannot be written.
  Recorder(runtime::Participant& p, const std::string& path, const std::vector<std::string>& topics)
      : Recorder(p, path, topics, format_of(path), McapCompression::zstd) {}
  // `derive` (MCAP only): messages each record gives, written after it.
  Recorder(runtime::Participant& p, const std::string& path, const std::vector<std::string>& topics,
           RecordingFormat format, McapCompression compression, Derive derive = nullptr);
  ~Recorder();
  // Stops recording, writes what is left and closes the file. Throws
  // std::runtime_error when writing it failed.
  void close();
  std::uint64_t samples() const;  // of the topics, written
  std::uint64_t derived() const;  // messages derived from them
  // Samples Fast DDS reports the readers will never receive, per topic,
  // as "Topic N, ..."; empty when none. After close(), those at close().
  std::string losses() const;
  // Samples dropped because the file fell kQueueBytes behind, likewise.
  std::string dropped() const;

  // What may wait for the file before samples are dropped: 11 s of the
  // default scene's camera frames alone (640x480x3 bytes at 25 Hz).
  static constexpr std::size_t kQueueBytes = std::size_t(256) << 20;

 private:
  struct Topic {
    std::function<void()> stop;  // takes no more on arrival, then what is left
    std::function<std::uint64_t()> lost;
    std::string name;
  };
  void push(Record&& r);  // on a receiving thread
  void write(const Record& r);
  void run();  // the writing thread

  mutable std::mutex m_;  // writer_, derive_, derived_, error_
  std::string path_;
  RecordingWriter writer_;
  Derive derive_;
  std::uint64_t derived_ = 0;
  std::string error_;          // the first failure to write
  std::vector<Topic> topics_;  // each owning its reader
  std::string losses_;         // losses() at close()

  mutable std::mutex queue_m_;  // the rest
  std::condition_variable queue_cv_;
  std::vector<Record> queue_;
  std::size_t queued_bytes_ = 0;
  bool closing_ = false;
  std::map<std::string, std::uint64_t> dropped_;  // by topic
  std::thread thread_;
};

}  // namespace hcosim::services::recording
