#include "services/recording/recording.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "idl/schemas.h"
#include "services/recording/bytes.h"
#include "services/runtime/service.h"

namespace hcosim::services::recording {
namespace {

// Samples of a few hundred bytes arrive at up to a few kHz: a recorder's
// writing thread wakes every 10 ms, or once a megabyte (a camera frame) waits.
constexpr auto kWritePeriod = std::chrono::milliseconds(10);
constexpr std::size_t kWakeBytes = std::size_t(1) << 20;

// What a queued record holds in memory, about.
std::size_t bytes_of(const Record& r) { return sizeof r + r.topic.size() + r.cdr.size(); }

constexpr char kMagic[8] = {'H', 'C', 'O', 'S', 'R', 'E', 'C', '1'};
// Large enough for a 1280x720 bgr8 frame; a larger length means a corrupt file.
constexpr std::uint32_t kMaxRecord = 64u << 20;

bool ends_with(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

}  // namespace

RecordingFormat format_of(const std::string& path) {
  return ends_with(path, ".mcap") ? RecordingFormat::mcap : RecordingFormat::hcosim;
}

RecordingFormat parse_recording_format(const std::string& name) {
  if (name == "hcosim") return RecordingFormat::hcosim;
  if (name == "mcap") return RecordingFormat::mcap;
  throw std::invalid_argument("unknown recording format '" + name + "': one of hcosim, mcap");
}

McapCompression parse_compression(const std::string& text) {
  for (const McapCompression c : {McapCompression::zstd, McapCompression::lz4, McapCompression::none})
    if (text == (c == McapCompression::none ? "none" : name(c))) return c;
  throw std::invalid_argument("unknown compression '" + text + "': one of zstd, lz4, none");
}

std::string idl_schema(const std::string& type_name) {
  const std::string scope = "hcosim::";
  if (type_name.rfind(scope, 0) != 0) throw std::invalid_argument("'" + type_name + "' is not an hcosim type");
  const std::string declares = "struct " + type_name.substr(scope.size()) + " {";
  std::string common;
  for (const idl::IdlText& f : idl::kIdlTexts)
    if (std::string(f.file) == "common") common = f.text;
  for (const idl::IdlText& f : idl::kIdlTexts)
    if (std::string(f.text).find(declares) != std::string::npos)
      return std::string(f.file) == "common" ? common : common + f.text;
  throw std::invalid_argument("no IDL file declares '" + type_name + "'");
}

RecordingWriter::RecordingWriter(const std::string& path, RecordingFormat format, McapCompression compression)
    : path_(path) {
  if (format == RecordingFormat::mcap) {
    mcap_ = std::make_unique<McapWriter>(path, compression);
    return;
  }
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error(path + ": cannot be written");
  out_.write(kMagic, sizeof kMagic);
}

void RecordingWriter::write(const Record& r) {
  if (mcap_) {
    auto it = channels_.find(r.topic);
    if (it == channels_.end()) {
      std::string type;
      runtime::with_topic(r.topic, [&](auto tag) { type = runtime::TopicOf<typename decltype(tag)::type>::type_name; });
      if (type.empty()) throw std::invalid_argument("a record of no contract topic '" + r.topic + "'");
      const std::uint16_t schema = mcap_->add_schema(type, "omgidl", idl_schema(type));
      it = channels_.emplace(r.topic, std::make_pair(mcap_->add_channel(schema, r.topic, "cdr"), 0u)).first;
    }
    write_mcap(it->second, r.receive_ns, r.publish_ns, r.cdr);
    return;
  }
  // u32 length of the rest, u16 topic length, topic, u64 step, i64 sim time,
  // i64 receive time, the CDR bytes.
  std::string b;
  append_le(b, std::uint16_t(r.topic.size()));
  b += r.topic;
  append_le(b, r.step);
  append_le(b, r.sim_time_ns);
  append_le(b, r.receive_ns);
  b.append(reinterpret_cast<const char*>(r.cdr.data()), r.cdr.size());
  std::string head;
  append_le(head, std::uint32_t(b.size()));
  out_.write(head.data(), std::streamsize(head.size()));
  out_.write(b.data(), std::streamsize(b.size()));
  ++count_;
}

void RecordingWriter::close() {
  if (mcap_) {
    mcap_->close();
    return;
  }
  out_.close();
  if (!out_) throw std::runtime_error(path_ + ": writing the recording failed");
}

void RecordingWriter::write(const Derived& d, std::int64_t receive_ns, std::int64_t publish_ns) {
  if (!mcap_) throw std::invalid_argument(path_ + ": derived channels go to MCAP recordings only");
  auto it = channels_.find(d.topic);
  if (it == channels_.end()) {
    auto schema = schemas_.find(d.schema_name);
    if (schema == schemas_.end())
      schema = schemas_.emplace(d.schema_name, mcap_->add_schema(d.schema_name, "omgidl", d.schema_text)).first;
    it = channels_.emplace(d.topic, std::make_pair(mcap_->add_channel(schema->second, d.topic, "cdr"), 0u)).first;
  }
  write_mcap(it->second, receive_ns, publish_ns, d.cdr);
}

void RecordingWriter::write_mcap(std::pair<std::uint16_t, std::uint32_t>& channel, std::int64_t receive_ns,
                                 std::int64_t publish_ns, const std::vector<std::uint8_t>& cdr) {
  McapMessage m;
  m.channel = channel.first;
  m.sequence = channel.second++;
  m.log_time = std::uint64_t(receive_ns);
  m.publish_time = std::uint64_t(publish_ns);
  m.data = cdr;
  mcap_->write(m);
  ++count_;
}

RecordingReader::RecordingReader(const std::string& path) : path_(path) {
  if (is_mcap(path)) {
    mcap_ = std::make_unique<McapReader>(path);
    return;
  }
  in_.open(path, std::ios::binary);
  if (!in_) throw std::runtime_error(path + ": cannot be read");
  char magic[sizeof kMagic] = {};
  in_.read(magic, sizeof magic);
  if (!in_ || std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw std::runtime_error(path + ": not an hcosim recording (docs/recording.md)");
  offset_ = sizeof kMagic;
}

bool RecordingReader::next_mcap(Record& r) {
  for (McapMessage m; mcap_->next(m);) {
    const McapChannel& c = mcap_->channels().at(m.channel);
    std::string type;
    runtime::with_topic(c.topic, [&](auto tag) { type = runtime::TopicOf<typename decltype(tag)::type>::type_name; });
    if (type.empty() || c.message_encoding != "cdr") {
      // The scene channels hcosim writes beside the topics are derived from them.
      const auto schema = mcap_->schemas().find(c.schema_id);
      if (schema == mcap_->schemas().end() || schema->second.name.rfind("foxglove::", 0) != 0) ++skipped_;
      continue;
    }
    const auto schema = mcap_->schemas().find(c.schema_id);
    if (schema == mcap_->schemas().end() || schema->second.name != type)
      throw std::runtime_error(path_ + ": channel " + std::to_string(c.id) + " '" + c.topic + "' has schema '" +
                               (schema == mcap_->schemas().end() ? std::string("none") : schema->second.name) +
                               "'; hcosim's " + c.topic + " is " + type);
    r.topic = c.topic;
    r.receive_ns = std::int64_t(m.log_time);
    r.publish_ns = std::int64_t(m.publish_time);
    r.cdr = std::move(m.data);
    r.step = 0, r.sim_time_ns = 0;
    runtime::with_topic(c.topic, [&](auto tag) {
      using T = typename decltype(tag)::type;
      const T s = from_cdr<T>(r.cdr);
      if constexpr (detail::HasStamp<T>::value) {
        r.step = s.stamp().step(), r.sim_time_ns = s.stamp().sim_time_ns();
      } else if constexpr (detail::HasStep<T>::value) {
        r.step = s.step();
      }
    });
    return true;
  }
  return false;
}

bool RecordingReader::next(Record& r) {
  if (mcap_) return next_mcap(r);
  char head[4];
  in_.read(head, 4);
  if (in_.gcount() == 0) return false;
  const std::string where = path_ + ": record at byte " + std::to_string(offset_);
  if (in_.gcount() != 4) throw std::runtime_error(where + " is cut short (an interrupted recording?)");
  const char* h = head;
  const std::uint32_t n = read_le<std::uint32_t>(h);
  if (n < 2 + 24 || n > kMaxRecord) throw std::runtime_error(where + " has an impossible length " + std::to_string(n));
  std::string b(n, '\0');
  in_.read(b.data(), n);
  if (std::uint32_t(in_.gcount()) != n) throw std::runtime_error(where + " is cut short (an interrupted recording?)");
  const char* p = b.data();
  const std::uint16_t t = read_le<std::uint16_t>(p);
  if (2u + t + 24u > n) throw std::runtime_error(where + " has an impossible topic length");
  r.topic.assign(p, t);
  p += t;
  r.step = read_le<std::uint64_t>(p);
  r.sim_time_ns = read_le<std::int64_t>(p);
  r.receive_ns = read_le<std::int64_t>(p);
  r.cdr.assign(reinterpret_cast<const std::uint8_t*>(p), reinterpret_cast<const std::uint8_t*>(b.data() + n));
  offset_ += 4 + n;
  return true;
}

Recorder::Recorder(runtime::Participant& p, const std::string& path, const std::vector<std::string>& topics,
                   RecordingFormat format, McapCompression compression, Derive derive)
    : path_(path),
      writer_(path, format, compression),
      derive_(format == RecordingFormat::mcap ? std::move(derive) : nullptr) {
  for (const std::string& t : topics) {
    if (!runtime::with_topic(t, [](auto) {})) throw std::invalid_argument("unknown topic '" + t + "'");
  }
  runtime::for_each_topic([&](auto tag) {
    using T = typename decltype(tag)::type;
    if (!topics.empty() && std::find(topics.begin(), topics.end(), runtime::TopicOf<T>::name) == topics.end()) return;
    // No validation: a recording keeps what was on the wire, bad samples included.
    auto reader =
        std::make_shared<runtime::Reader<T>>(p, nullptr, nullptr, runtime::TopicOf<T>::qos, runtime::kMonitorDepth);
    auto take = [this, r = reader.get()] { r->take([&](const T& s) { push(make_record(s, runtime::wall_ns())); }); };
    reader->on_arrival(take);
    topics_.push_back({[reader, take] {
                         reader->on_arrival(nullptr);
                         take();
                       },
                       [reader] { return reader->lost(); }, runtime::TopicOf<T>::name});
  });
  // Last, so that nothing above throws with it running; what arrives
  // before it starts waits in the queue.
  thread_ = std::thread([this] { run(); });
}

Recorder::~Recorder() {
  try {
    close();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hcosim: recording %s: %s\n", path_.c_str(), e.what());
  }
}

void Recorder::push(Record&& r) {
  const std::size_t bytes = bytes_of(r);
  bool wake = false;
  {
    std::lock_guard<std::mutex> l(queue_m_);
    if (queued_bytes_ + bytes > kQueueBytes) {
      ++dropped_[r.topic];
      return;
    }
    wake = queued_bytes_ < kWakeBytes && queued_bytes_ + bytes >= kWakeBytes;
    queued_bytes_ += bytes;
    queue_.push_back(std::move(r));
  }
  if (wake) queue_cv_.notify_one();
}

void Recorder::write(const Record& r) {
  std::lock_guard<std::mutex> l(m_);
  if (!error_.empty()) return;
  try {
    writer_.write(r);
    if (!derive_) return;
    try {
      for (const Derived& d : derive_(r)) writer_.write(d, r.receive_ns, r.publish_ns), ++derived_;
    } catch (const std::exception& e) {
      // The topics go on, the scene stops.
      std::fprintf(stderr, "hcosim: recording %s: no more scene channels: %s\n", path_.c_str(), e.what());
      derive_ = nullptr;
    }
  } catch (const std::exception& e) {
    error_ = e.what();
  }
}

void Recorder::run() {
  std::vector<Record> batch;
  for (bool last = false; !last;) {
    {
      std::unique_lock<std::mutex> l(queue_m_);
      queue_cv_.wait_for(l, kWritePeriod, [&] { return closing_ || queued_bytes_ >= kWakeBytes; });
      batch.swap(queue_);
      last = closing_;
    }
    std::size_t bytes = 0;
    for (const Record& r : batch) {
      write(r);
      bytes += bytes_of(r);
    }
    batch.clear();
    std::lock_guard<std::mutex> l(queue_m_);
    queued_bytes_ -= bytes;
  }
}

std::uint64_t Recorder::samples() const {
  std::lock_guard<std::mutex> l(m_);
  return writer_.count() - derived_;
}

std::uint64_t Recorder::derived() const {
  std::lock_guard<std::mutex> l(m_);
  return derived_;
}

std::string Recorder::losses() const {
  if (topics_.empty()) return losses_;
  std::string out;
  for (const auto& t : topics_)
    if (const std::uint64_t n = t.lost()) out += (out.empty() ? "" : ", ") + t.name + " " + std::to_string(n);
  return out;
}

std::string Recorder::dropped() const {
  std::lock_guard<std::mutex> l(queue_m_);
  std::string out;
  for (const auto& [topic, n] : dropped_) out += (out.empty() ? "" : ", ") + topic + " " + std::to_string(n);
  return out;
}

void Recorder::close() {
  if (!thread_.joinable()) return;
  for (auto& t : topics_) t.stop();
  losses_ = losses();
  topics_.clear();
  {
    std::lock_guard<std::mutex> l(queue_m_);
    closing_ = true;
  }
  queue_cv_.notify_one();
  thread_.join();
  if (!error_.empty()) throw std::runtime_error(path_ + ": writing the recording failed: " + error_);
  writer_.close();
}

}  // namespace hcosim::services::recording
