// MCAP (mcap.dev, Foxglove's container for recorded messages): a chunked
// writer with message and chunk indexes and a summary, so that tools seek,
// and a reader of the messages in file order. Our own small codec over
// zstd, lz4 and zlib's CRC-32: Debian 12 has no MCAP library. Layout and
// limits in docs/recording.md.
#pragma once

#include <cstdint>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace hcosim::services::recording {

enum class McapCompression { none, zstd, lz4 };
const char* name(McapCompression c);  // as MCAP spells it: "", "zstd", "lz4"

struct McapSchema {
  std::uint16_t id = 0;
  std::string name, encoding, data;
};

struct McapChannel {
  std::uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};

struct McapMessage {
  std::uint16_t channel = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0, publish_time = 0;  // ns
  std::vector<std::uint8_t> data;
};

// Writes a new file: magic and header, then schemas, channels and messages
// in chunks of about `chunk_bytes` (uncompressed) each followed by its
// message indexes, then the summary (schemas, channels, statistics, chunk
// indexes, their offsets) and the footer. Throws std::runtime_error naming
// the file when it cannot be written.
class McapWriter {
 public:
  McapWriter(const std::string& path, McapCompression compression, std::size_t chunk_bytes = 1 << 20);
  ~McapWriter();  // closes, swallowing errors: call close() to learn of them
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Each returns the new record's id (from 1); a channel's schema must exist.
  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                            const std::map<std::string, std::string>& metadata = {});
  void write(const McapMessage& m);
  void close();  // throws if anything failed to reach the disk
  std::uint64_t messages() const { return messages_; }

 private:
  void flush_chunk();
  void emit(const std::string& record);  // to the file, CRC and offset kept

  std::string path_;
  std::ofstream out_;
  McapCompression compression_;
  std::size_t chunk_bytes_;
  bool closed_ = false;
  std::uint64_t offset_ = 0;
  std::uint32_t data_crc_ = 0;
  std::vector<McapSchema> schemas_;
  std::vector<McapChannel> channels_;
  // The open chunk: its records, time span, and per channel (log time,
  // offset in the chunk) of each message.
  std::string chunk_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::vector<std::string> chunk_indexes_;  // ChunkIndex records, for the summary
  std::map<std::uint16_t, std::uint64_t> counts_;
  std::uint64_t messages_ = 0, first_ = 0, last_ = 0;
};

// True when the file at `path` begins with MCAP's magic.
bool is_mcap(const std::string& path);

// Reads messages in file order, the schemas and channels seen before them
// (in or out of chunks). Checks each chunk's CRC and the data section's
// when they are given (not 0). Throws std::runtime_error naming the file
// and byte offset for a file that is not MCAP, is cut short, or is corrupt.
class McapReader {
 public:
  explicit McapReader(const std::string& path);
  bool next(McapMessage& m);  // false at the data section's end
  const std::map<std::uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }

 private:
  // One record of the data section at top level; false at its end.
  bool read_record(std::uint8_t& op, std::string& body);
  // A schema or channel record; a message goes to `m`, true then.
  bool take(std::uint8_t op, const std::string& body, McapMessage* m, const std::string& where);

  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;  // the file's
  std::uint64_t offset_ = 0;
  std::uint32_t crc_ = 0;
  bool ended_ = false;
  std::string chunk_;  // the open chunk's records, decompressed
  std::size_t chunk_at_ = 0;
  std::uint64_t record_at_ = 0;  // the last top-level record's place in the file
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, McapChannel> channels_;
};

}  // namespace hcosim::services::recording
