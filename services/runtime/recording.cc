#include "services/runtime/recording.h"

#include <cstring>
#include <stdexcept>

#include "services/runtime/service.h"

namespace hcosim::services::runtime {
namespace {

constexpr char kMagic[8] = {'H', 'C', 'O', 'S', 'R', 'E', 'C', '1'};
// Large enough for a 1280x720 bgr8 frame; a larger length means a corrupt file.
constexpr std::uint32_t kMaxRecord = 64u << 20;

template <class U>
void put(std::string& out, U v) {
  char b[sizeof(U)];
  std::memcpy(b, &v, sizeof(U));  // little-endian on every machine hcosim builds for
  out.append(b, sizeof(U));
}

template <class U>
U get(const char*& p) {
  U v;
  std::memcpy(&v, p, sizeof(U));
  p += sizeof(U);
  return v;
}

}  // namespace

RecordingWriter::RecordingWriter(const std::string& path)
    : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw std::runtime_error(path + ": cannot be written");
  out_.write(kMagic, sizeof kMagic);
}

void RecordingWriter::write(const Record& r) {
  // u32 length of the rest, u16 topic length, topic, u64 step, i64 sim time,
  // i64 receive time, the CDR bytes.
  std::string b;
  put(b, std::uint16_t(r.topic.size()));
  b += r.topic;
  put(b, r.step);
  put(b, r.sim_time_ns);
  put(b, r.receive_ns);
  b.append(reinterpret_cast<const char*>(r.cdr.data()), r.cdr.size());
  std::string head;
  put(head, std::uint32_t(b.size()));
  out_.write(head.data(), std::streamsize(head.size()));
  out_.write(b.data(), std::streamsize(b.size()));
  ++count_;
}

void RecordingWriter::close() {
  out_.close();
  if (!out_) throw std::runtime_error(path_ + ": writing the recording failed");
}

RecordingReader::RecordingReader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
  if (!in_) throw std::runtime_error(path + ": cannot be read");
  char magic[sizeof kMagic] = {};
  in_.read(magic, sizeof magic);
  if (!in_ || std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw std::runtime_error(path + ": not an hcosim recording (docs/recording.md)");
  offset_ = sizeof kMagic;
}

bool RecordingReader::next(Record& r) {
  char head[4];
  in_.read(head, 4);
  if (in_.gcount() == 0) return false;
  const std::string where = path_ + ": record at byte " + std::to_string(offset_);
  if (in_.gcount() != 4) throw std::runtime_error(where + " is cut short (an interrupted recording?)");
  const char* h = head;
  const std::uint32_t n = get<std::uint32_t>(h);
  if (n < 2 + 24 || n > kMaxRecord) throw std::runtime_error(where + " has an impossible length " + std::to_string(n));
  std::string b(n, '\0');
  in_.read(b.data(), n);
  if (std::uint32_t(in_.gcount()) != n) throw std::runtime_error(where + " is cut short (an interrupted recording?)");
  const char* p = b.data();
  const std::uint16_t t = get<std::uint16_t>(p);
  if (2u + t + 24u > n) throw std::runtime_error(where + " has an impossible topic length");
  r.topic.assign(p, t);
  p += t;
  r.step = get<std::uint64_t>(p);
  r.sim_time_ns = get<std::int64_t>(p);
  r.receive_ns = get<std::int64_t>(p);
  r.cdr.assign(reinterpret_cast<const std::uint8_t*>(p), reinterpret_cast<const std::uint8_t*>(b.data() + n));
  offset_ += 4 + n;
  return true;
}

Recorder::Recorder(Participant& p, const std::string& path, const std::vector<std::string>& topics) : writer_(path) {
  for (const std::string& t : topics) {
    if (!with_topic(t, [](auto) {})) throw std::invalid_argument("unknown topic '" + t + "'");
  }
  for_each_topic([&](auto tag) {
    using T = typename decltype(tag)::type;
    if (!topics.empty() && std::find(topics.begin(), topics.end(), TopicOf<T>::name) == topics.end()) return;
    // No validation: a recording keeps what was on the wire, bad samples included.
    auto reader = std::make_shared<Reader<T>>(p, nullptr, nullptr, TopicOf<T>::qos, kMonitorDepth);
    auto take = [this, r = reader.get()] {
      r->take([&](const T& s) {
        Record rec = make_record(s, wall_ns());
        std::lock_guard<std::mutex> l(m_);
        writer_.write(rec);
      });
    };
    reader->on_arrival(take);
    topics_.push_back({[reader, take] {
                         reader->on_arrival(nullptr);
                         take();
                       },
                       [reader] { return reader->lost(); }, TopicOf<T>::name});
  });
}

std::uint64_t Recorder::samples() const {
  std::lock_guard<std::mutex> l(m_);
  return writer_.count();
}

std::string Recorder::losses() const {
  if (topics_.empty()) return losses_;
  std::string out;
  for (const auto& t : topics_)
    if (const std::uint64_t n = t.lost()) out += (out.empty() ? "" : ", ") + t.name + " " + std::to_string(n);
  return out;
}

void Recorder::close() {
  for (auto& t : topics_) t.stop();
  losses_ = losses();
  topics_.clear();
  writer_.close();
}

}  // namespace hcosim::services::runtime
