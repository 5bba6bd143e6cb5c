#pragma once
// A small MCAP writer (https://mcap.dev/spec; no C++ MCAP library is packaged in Debian 12):
// Header, Schemas and Channels in the data section, Messages in uncompressed Chunks (each
// followed by its Message Index records), then Data End (with the data section's CRC-32), a
// summary (Schemas, Channels, Statistics, Chunk Indexes), Summary Offsets and the Footer (with
// the summary's CRC-32). Indexed readers (@mcap/core's McapIndexedReader, Foxglove) seek by
// it; streaming readers read it front to back.
//
//   auto w = McapWriter::create("run.mcap", /*overwrite=*/false).value();
//   TLV_TRY(w->add_schema({1, "tlvlink.Stats", "jsonschema", schema_text}));
//   TLV_TRY(w->add_channel({1, 1, "/tlvlink/stats", "json", {}}));
//   TLV_TRY(w->write_message(1, log_ns, publish_ns, bytes));
//   TLV_TRY(w->close());
//
// Not thread-safe: one thread writes. Write errors name the path and the reason ("disk full").

#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/foxglove/mcap_records.h"

namespace tlvlink::foxglove {

struct McapWriterOptions {
  std::string profile;              // the Header's profile ("" : none of the well-known ones)
  std::string library = "tlvlink";  // the Header's library
  size_t chunk_bytes = 256 * 1024;  // close a chunk at this many bytes of records...
  uint64_t chunk_span_ns =
      1'000'000'000;  // ...or when its messages span this long (bounds what a crash loses)
};

class McapWriter {
 public:
  // Creates `path` by the recordings' rule (listen::create_recording_file: an existing file only
  // with `overwrite`; a FIFO or device refused) and writes the magic and the Header.
  static Result<std::unique_ptr<McapWriter>> create(const std::string& path, bool overwrite,
                                                    const McapWriterOptions& options = {});
  ~McapWriter();  // closes the file if close() was not called (an error is then lost)
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Schemas and channels go into the data section at once (before messages that use them) and
  // are repeated in the summary. Ids must be new; a channel's schema must have been added.
  Status add_schema(const McapSchema& schema);
  Status add_channel(const McapChannel& channel);
  // Log and publish times in ns. The channel must have been added.
  Status write_message(uint16_t channel_id, uint64_t log_time, uint64_t publish_time,
                       std::span<const std::byte> data);
  // Writes what is buffered to the file (a closed chunk); the open chunk stays in memory.
  Status flush();
  // Closes the last chunk, writes Data End, the summary and the Footer, and closes the file.
  Status close();

  uint64_t message_count() const { return message_count_; }
  // A write failed (every later call returns that error).
  bool failed() const { return failed_.has_value(); }
  const std::string& path() const { return path_; }

 private:
  McapWriter(std::FILE* file, std::string path, McapWriterOptions options);
  Status put(std::span<const std::byte> bytes, bool data_section);
  Status put_record(uint8_t opcode, std::span<const std::byte> content, bool data_section);
  Status close_chunk();

  std::FILE* file_;
  std::string path_;
  McapWriterOptions options_;
  std::optional<Error> failed_;  // the first write error; every later call returns it
  bool closed_ = false;
  uint64_t position_ = 0;  // bytes written so far
  uint32_t data_crc_ = 0;  // CRC-32 of the data section so far (from the magic on)
  std::map<uint16_t, McapSchema> schemas_;
  std::map<uint16_t, McapChannel> channels_;
  std::map<uint16_t, uint32_t> next_sequence_;
  std::map<uint16_t, uint64_t> channel_counts_;
  uint64_t message_count_ = 0, first_time_ = UINT64_MAX, last_time_ = 0;
  // The open chunk: its records, and per channel (log time, offset in the records).
  std::vector<std::byte> chunk_;
  uint64_t chunk_start_ = UINT64_MAX, chunk_end_ = 0;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;
  std::vector<std::vector<std::byte>>
      chunk_indexes_;  // ChunkIndex record contents, for the summary
};

}  // namespace tlvlink::foxglove
