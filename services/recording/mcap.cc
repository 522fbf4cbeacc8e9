#include "services/recording/mcap.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include "services/recording/bytes.h"

namespace hcosim::services::recording {
namespace {

constexpr char kMcapMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
// Record opcodes of the MCAP specification.
enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};
// A chunk larger than this, decompressed, means a corrupt file (ours are
// about 1 MiB, or one message: a 1280x720 frame is 2.8 MB).
constexpr std::uint64_t kMaxChunk = 256ull << 20;

std::uint32_t crc(std::uint32_t c, const void* p, std::size_t n) {
  return std::uint32_t(crc32_z(c, static_cast<const Bytef*>(p), n));
}

// Little-endian integers, strings and maps as the specification lays them out.
void put_string(std::string& out, const std::string& s) {
  append_le(out, std::uint32_t(s.size()));
  out += s;
}

std::string record(Op op, const std::string& body) {
  std::string r;
  append_le(r, std::uint8_t(op));
  append_le(r, std::uint64_t(body.size()));
  return r + body;
}

// Reads a record's fields, naming where it is when one runs past its end.
struct Cursor {
  const char* p;
  const char* end;
  const std::string& where;

  void need(std::size_t n) const {
    if (std::size_t(end - p) < n) throw std::runtime_error(where + " is cut short");
  }
  template <class U>
  U get() {
    need(sizeof(U));
    U v;
    std::memcpy(&v, p, sizeof(U));
    p += sizeof(U);
    return v;
  }
  std::string bytes(std::uint64_t n) {
    need(n);
    std::string s(p, n);
    p += n;
    return s;
  }
  std::string string() { return bytes(get<std::uint32_t>()); }
  std::map<std::string, std::string> string_map() {
    const std::uint32_t n = get<std::uint32_t>();
    need(n);
    Cursor in{p, p + n, where};
    std::map<std::string, std::string> m;
    while (in.p < in.end) {
      std::string k = in.string();
      m[k] = in.string();
    }
    p += n;
    return m;
  }
};

std::string compress(McapCompression c, const std::string& raw) {
  if (c == McapCompression::none) return raw;
  if (c == McapCompression::zstd) {
    std::string out(ZSTD_compressBound(raw.size()), '\0');
    const std::size_t n = ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), 3);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("mcap: zstd: ") + ZSTD_getErrorName(n));
    out.resize(n);
    return out;
  }
  std::string out(LZ4F_compressFrameBound(raw.size(), nullptr), '\0');
  const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), raw.data(), raw.size(), nullptr);
  if (LZ4F_isError(n)) throw std::runtime_error(std::string("mcap: lz4: ") + LZ4F_getErrorName(n));
  out.resize(n);
  return out;
}

std::string decompress(const std::string& how, const std::string& packed, std::uint64_t size,
                       const std::string& where) {
  if (how.empty()) {
    if (packed.size() != size)
      throw std::runtime_error(where + ": an uncompressed chunk of " + std::to_string(packed.size()) +
                               " bytes says it holds " + std::to_string(size));
    return packed;
  }
  std::string out(size, '\0');
  if (how == "zstd") {
    if (ZSTD_getFrameContentSize(packed.data(), packed.size()) != size)
      throw std::runtime_error(where + ": zstd chunk does not say it holds its " + std::to_string(size) + " bytes");
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), packed.data(), packed.size());
    if (ZSTD_isError(n) || n != size)
      throw std::runtime_error(where + ": zstd chunk does not decompress to its " + std::to_string(size) + " bytes");
    return out;
  }
  if (how == "lz4") {
    LZ4F_dctx* d = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&d, LZ4F_VERSION)))
      throw std::runtime_error(where + ": lz4 context");
    const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> hold(d, &LZ4F_freeDecompressionContext);
    std::size_t in_at = 0, out_at = 0;
    while (in_at < packed.size()) {
      std::size_t in_n = packed.size() - in_at, out_n = out.size() - out_at;
      const std::size_t r = LZ4F_decompress(d, out.data() + out_at, &out_n, packed.data() + in_at, &in_n, nullptr);
      if (LZ4F_isError(r)) throw std::runtime_error(where + ": lz4: " + LZ4F_getErrorName(r));
      in_at += in_n, out_at += out_n;
      if (r == 0) break;
      if (in_n == 0 && out_n == 0) break;
    }
    if (out_at != size)
      throw std::runtime_error(where + ": lz4 chunk does not decompress to its " + std::to_string(size) + " bytes");
    return out;
  }
  throw std::runtime_error(where + ": compression '" + how + "' is not one of zstd, lz4 or none");
}

std::string schema_body(const McapSchema& s) {
  std::string b;
  append_le(b, s.id);
  put_string(b, s.name);
  put_string(b, s.encoding);
  put_string(b, s.data);
  return b;
}

std::string channel_body(const McapChannel& c) {
  std::string b, m;
  append_le(b, c.id);
  append_le(b, c.schema_id);
  put_string(b, c.topic);
  put_string(b, c.message_encoding);
  for (const auto& [k, v] : c.metadata) put_string(m, k), put_string(m, v);
  put_string(b, m);
  return b;
}

}  // namespace

const char* name(McapCompression c) {
  switch (c) {
    case McapCompression::none:
      return "";
    case McapCompression::zstd:
      return "zstd";
    case McapCompression::lz4:
      return "lz4";
  }
  return "?";
}

McapWriter::McapWriter(const std::string& path, McapCompression compression, std::size_t chunk_bytes)
    : path_(path),
      out_(path, std::ios::binary | std::ios::trunc),
      compression_(compression),
      chunk_bytes_(chunk_bytes) {
  if (!out_) throw std::runtime_error(path + ": cannot be written");
  emit(std::string(kMcapMagic, sizeof kMcapMagic));
  std::string header;
  put_string(header, "");  // profile: none of the well-known ones
  put_string(header, "hcosim");
  emit(record(kHeader, header));
}

McapWriter::~McapWriter() {
  try {
    close();
  } catch (const std::exception&) {
  }
}

void McapWriter::emit(const std::string& r) {
  out_.write(r.data(), std::streamsize(r.size()));
  data_crc_ = crc(data_crc_, r.data(), r.size());
  offset_ += r.size();
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  if (schemas_.size() >= 65535) throw std::runtime_error(path_ + ": more than 65535 schemas");
  schemas_.push_back({std::uint16_t(schemas_.size() + 1), name, encoding, data});
  chunk_ += record(kSchema, schema_body(schemas_.back()));
  return schemas_.back().id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, const std::string& topic,
                                      const std::string& message_encoding,
                                      const std::map<std::string, std::string>& metadata) {
  if (schema_id == 0 || schema_id > schemas_.size())
    throw std::invalid_argument("mcap: channel '" + topic + "' names no schema " + std::to_string(schema_id));
  if (channels_.size() >= 65535) throw std::runtime_error(path_ + ": more than 65535 channels");
  channels_.push_back({std::uint16_t(channels_.size() + 1), schema_id, topic, message_encoding, metadata});
  chunk_ += record(kChannel, channel_body(channels_.back()));
  return channels_.back().id;
}

void McapWriter::write(const McapMessage& m) {
  if (m.channel == 0 || m.channel > channels_.size())
    throw std::invalid_argument("mcap: a message on no channel " + std::to_string(m.channel));
  std::string b;
  append_le(b, m.channel);
  append_le(b, m.sequence);
  append_le(b, m.log_time);
  append_le(b, m.publish_time);
  b.append(reinterpret_cast<const char*>(m.data.data()), m.data.size());
  if (chunk_index_.empty()) chunk_start_ = chunk_end_ = m.log_time;
  chunk_start_ = std::min(chunk_start_, m.log_time), chunk_end_ = std::max(chunk_end_, m.log_time);
  chunk_index_[m.channel].push_back({m.log_time, chunk_.size()});
  chunk_ += record(kMessage, b);
  if (messages_ == 0) first_ = last_ = m.log_time;
  first_ = std::min(first_, m.log_time), last_ = std::max(last_, m.log_time);
  ++counts_[m.channel], ++messages_;
  if (chunk_.size() >= chunk_bytes_) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  const std::string packed = compress(compression_, chunk_);
  std::string c;
  append_le(c, chunk_start_);
  append_le(c, chunk_end_);
  append_le(c, std::uint64_t(chunk_.size()));
  append_le(c, crc(0, chunk_.data(), chunk_.size()));
  put_string(c, name(compression_));
  append_le(c, std::uint64_t(packed.size()));
  c += packed;
  const std::uint64_t chunk_at = offset_;
  emit(record(kChunk, c));
  const std::uint64_t chunk_length = offset_ - chunk_at;
  // Each channel's message index, its entries in log time order.
  std::string offsets;
  for (auto& [channel, entries] : chunk_index_) {
    std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::string b;
    append_le(b, channel);
    append_le(b, std::uint32_t(entries.size() * 16));
    for (const auto& [t, at] : entries) append_le(b, t), append_le(b, at);
    append_le(offsets, channel);
    append_le(offsets, offset_);
    emit(record(kMessageIndex, b));
  }
  std::string index;
  append_le(index, chunk_start_);
  append_le(index, chunk_end_);
  append_le(index, chunk_at);
  append_le(index, chunk_length);
  put_string(index, offsets);
  append_le(index, offset_ - chunk_at - chunk_length);
  put_string(index, name(compression_));
  append_le(index, std::uint64_t(packed.size()));
  append_le(index, std::uint64_t(chunk_.size()));
  chunk_indexes_.push_back(record(kChunkIndex, index));
  chunk_.clear();
  chunk_index_.clear();
  chunk_start_ = chunk_end_ = 0;
}

void McapWriter::close() {
  if (closed_) return;
  closed_ = true;
  flush_chunk();
  std::string end;
  append_le(end, data_crc_);
  emit(record(kDataEnd, end));

  // The summary: every schema and channel, the statistics and the chunk
  // indexes, each kind a group whose place the summary offsets give.
  const std::uint64_t summary_at = offset_;
  data_crc_ = 0;  // from here the summary's CRC
  std::vector<std::string> offsets;
  auto group = [&](Op op, const std::vector<std::string>& records) {
    if (records.empty()) return;
    const std::uint64_t at = offset_;
    for (const std::string& r : records) emit(r);
    std::string o;
    append_le(o, std::uint8_t(op));
    append_le(o, at);
    append_le(o, offset_ - at);
    offsets.push_back(record(kSummaryOffset, o));
  };
  std::vector<std::string> schemas, channels;
  for (const McapSchema& s : schemas_) schemas.push_back(record(kSchema, schema_body(s)));
  for (const McapChannel& c : channels_) channels.push_back(record(kChannel, channel_body(c)));
  std::string stats, counts;
  append_le(stats, messages_);
  append_le(stats, std::uint16_t(schemas_.size()));
  append_le(stats, std::uint32_t(channels_.size()));
  append_le(stats, std::uint32_t(0));  // attachments
  append_le(stats, std::uint32_t(0));  // metadata
  append_le(stats, std::uint32_t(chunk_indexes_.size()));
  append_le(stats, first_);
  append_le(stats, last_);
  for (const auto& [channel, n] : counts_) append_le(counts, channel), append_le(counts, n);
  put_string(stats, counts);
  group(kSchema, schemas);
  group(kChannel, channels);
  group(kStatistics, {record(kStatistics, stats)});
  group(kChunkIndex, chunk_indexes_);
  const std::uint64_t offsets_at = offset_;
  for (const std::string& o : offsets) emit(o);
  std::string footer;
  append_le(footer, std::uint8_t(kFooter));
  append_le(footer, std::uint64_t(20));
  append_le(footer, summary_at);
  append_le(footer, offsets_at);
  append_le(footer, crc(data_crc_, footer.data(), footer.size()));
  emit(footer);
  emit(std::string(kMcapMagic, sizeof kMcapMagic));
  out_.close();
  if (!out_) throw std::runtime_error(path_ + ": writing the recording failed");
}

bool is_mcap(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[sizeof kMcapMagic] = {};
  in.read(magic, sizeof magic);
  return in && std::memcmp(magic, kMcapMagic, sizeof kMcapMagic) == 0;
}

McapReader::McapReader(const std::string& path) : path_(path), in_(path, std::ios::binary | std::ios::ate) {
  if (!in_) throw std::runtime_error(path + ": cannot be read");
  size_ = std::uint64_t(in_.tellg());
  in_.seekg(0);
  char magic[sizeof kMcapMagic] = {};
  in_.read(magic, sizeof magic);
  if (!in_ || std::memcmp(magic, kMcapMagic, sizeof kMcapMagic) != 0)
    throw std::runtime_error(path + ": not an MCAP file");
  crc_ = crc(0, magic, sizeof magic);
  offset_ = sizeof magic;
  std::uint8_t op = 0;
  std::string body;
  if (!read_record(op, body) || op != kHeader)
    throw std::runtime_error(path + ": MCAP's first record is not its header");
}

bool McapReader::read_record(std::uint8_t& op, std::string& body) {
  if (ended_) return false;
  const std::string where = path_ + ": record at byte " + std::to_string(offset_);
  char head[9];
  in_.read(head, sizeof head);
  if (in_.gcount() == 0) return ended_ = true, false;  // no data end: a recording cut off, all of it read
  if (in_.gcount() != sizeof head) throw std::runtime_error(where + " is cut short (an interrupted recording?)");
  op = std::uint8_t(head[0]);
  std::uint64_t n;
  std::memcpy(&n, head + 1, 8);
  if (n > size_ - offset_ - sizeof head)
    throw std::runtime_error(where + " is cut short (an interrupted recording?): " + std::to_string(n) +
                             " bytes long, " + std::to_string(size_ - offset_ - sizeof head) + " left");
  body.assign(n, '\0');
  in_.read(body.data(), std::streamsize(n));
  if (std::uint64_t(in_.gcount()) != n) throw std::runtime_error(where + " is cut short (an interrupted recording?)");
  if (op == kDataEnd) {
    Cursor c{body.data(), body.data() + body.size(), where};
    const std::uint32_t want = c.get<std::uint32_t>();
    if (want != 0 && want != crc_)
      throw std::runtime_error(where + ": the data section's CRC does not match (a corrupt file)");
    return ended_ = true, false;
  }
  crc_ = crc(crc(crc_, head, sizeof head), body.data(), body.size());
  record_at_ = offset_;
  offset_ += sizeof head + n;
  return true;
}

bool McapReader::take(std::uint8_t op, const std::string& body, McapMessage* m, const std::string& where) {
  Cursor c{body.data(), body.data() + body.size(), where};
  if (op == kSchema) {
    McapSchema s;
    s.id = c.get<std::uint16_t>();
    s.name = c.string();
    s.encoding = c.string();
    s.data = c.string();
    schemas_[s.id] = s;
  } else if (op == kChannel) {
    McapChannel ch;
    ch.id = c.get<std::uint16_t>();
    ch.schema_id = c.get<std::uint16_t>();
    ch.topic = c.string();
    ch.message_encoding = c.string();
    ch.metadata = c.string_map();
    channels_[ch.id] = ch;
  } else if (op == kMessage) {
    m->channel = c.get<std::uint16_t>();
    m->sequence = c.get<std::uint32_t>();
    m->log_time = c.get<std::uint64_t>();
    m->publish_time = c.get<std::uint64_t>();
    m->data.assign(reinterpret_cast<const std::uint8_t*>(c.p), reinterpret_cast<const std::uint8_t*>(c.end));
    if (!channels_.count(m->channel))
      throw std::runtime_error(where + ": a message on channel " + std::to_string(m->channel) +
                               ", which no channel record before it declares");
    return true;
  }
  return false;  // the other records say nothing a reader in file order needs
}

bool McapReader::next(McapMessage& m) {
  for (;;) {
    if (chunk_at_ < chunk_.size()) {
      const std::string where =
          path_ + ": chunk at byte " + std::to_string(record_at_) + ", its record at " + std::to_string(chunk_at_);
      Cursor c{chunk_.data() + chunk_at_, chunk_.data() + chunk_.size(), where};
      const std::uint8_t op = c.get<std::uint8_t>();
      const std::string body = c.bytes(c.get<std::uint64_t>());
      chunk_at_ = std::size_t(c.p - chunk_.data());
      if (take(op, body, &m, where)) return true;
      continue;
    }
    std::uint8_t op = 0;
    std::string body;
    if (!read_record(op, body)) return false;
    const std::string where = path_ + ": record at byte " + std::to_string(record_at_);
    if (op == kChunk) {
      Cursor c{body.data(), body.data() + body.size(), where};
      c.get<std::uint64_t>(), c.get<std::uint64_t>();  // its time span
      const std::uint64_t size = c.get<std::uint64_t>();
      const std::uint32_t want = c.get<std::uint32_t>();
      const std::string how = c.string();
      const std::string packed = c.bytes(c.get<std::uint64_t>());
      if (size > kMaxChunk)
        throw std::runtime_error(where + ": a chunk of " + std::to_string(size) + " bytes, over the " +
                                 std::to_string(kMaxChunk >> 20) + " MiB that hcosim reads");
      chunk_ = decompress(how, packed, size, where);
      if (want != 0 && crc(0, chunk_.data(), chunk_.size()) != want)
        throw std::runtime_error(where + ": the chunk's CRC does not match (a corrupt file)");
      chunk_at_ = 0;
      continue;
    }
    if (take(op, body, &m, where)) return true;
  }
}

}  // namespace hcosim::services::recording
