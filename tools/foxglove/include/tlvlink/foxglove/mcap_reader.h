#pragma once
// Reads an MCAP file front to back (https://mcap.dev/spec): enough for tlvlink's own files and
// for any well-formed uncompressed file: schemas, channels and every message (inside chunks or
// not), the Statistics. Files are untrusted input: every bad byte is an error that names the
// record, the field and its offset (bad magic, a record longer than what remains, a chunk with
// an unsupported compression or a wrong CRC, a message on an unknown channel, a data section or
// summary CRC mismatch, Statistics that disagree with the messages, no Footer). Records of
// kinds this reader does not use (attachments, metadata, indexes) are checked for length and
// skipped, as the spec asks.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/foxglove/mcap_records.h"

namespace tlvlink::foxglove {

struct McapStatistics {
  uint64_t message_count = 0;
  uint32_t channel_count = 0, chunk_count = 0;
  uint16_t schema_count = 0;
  uint64_t message_start_time = 0, message_end_time = 0;
};

struct McapFile {
  std::string profile, library;     // the Header's
  std::vector<McapSchema> schemas;  // in file order, each id once
  std::vector<McapChannel> channels;
  std::vector<McapMessage> messages;  // in file order
  std::optional<McapStatistics> statistics;
  bool summary_crc_checked = false,
       data_crc_checked = false;  // the CRCs were present (non-zero) and matched

  const McapChannel* channel(uint16_t id) const;
  const McapSchema* schema(uint16_t id) const;
};

// `name` is the file's name in errors.
Result<McapFile> read_mcap(std::span<const std::byte> bytes, const std::string& name);
Result<McapFile> read_mcap_file(const std::string& path);

}  // namespace tlvlink::foxglove
