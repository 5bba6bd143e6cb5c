#pragma once
// Little-endian fields of MCAP records: appending them (the writer) and reading them with bounds
// checks that name the field and its file offset (the reader). Internal to tlvlink_foxglove.
#ifndef TLVLINK_FOXGLOVE_PRIVATE
#error "mcap_bytes.h is internal to tlvlink_foxglove"
#endif

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::foxglove::internal {

enum Opcode : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};
const char* opcode_name(uint8_t op);  // "Message", or "unknown"

// Record framing: opcode u8, content length u64.
inline constexpr size_t kRecordPrefix = 9;

class ByteWriter {
 public:
  void u8(uint8_t v) { bytes_.push_back(std::byte{v}); }
  void u16(uint16_t v) { le(v, 2); }
  void u32(uint32_t v) { le(v, 4); }
  void u64(uint64_t v) { le(v, 8); }
  void str(std::string_view s) {  // u32 length + bytes
    u32(static_cast<uint32_t>(s.size()));
    raw(std::as_bytes(std::span(s.data(), s.size())));
  }
  void raw(std::span<const std::byte> b) { bytes_.insert(bytes_.end(), b.begin(), b.end()); }
  void patch_u32(size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_[at + i] = std::byte((v >> (8 * i)) & 0xFF);
  }
  size_t size() const { return bytes_.size(); }
  std::vector<std::byte>& bytes() { return bytes_; }

 private:
  void le(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) bytes_.push_back(std::byte((v >> (8 * i)) & 0xFF));
  }
  std::vector<std::byte> bytes_;
};

// Reads one record's content. The first failure is kept (later reads return zeros) and names
// the record, the field and the file offset; callers check error() once per record.
class ByteReader {
 public:
  ByteReader(std::span<const std::byte> data, uint64_t file_offset, const char* record)
      : data_(data), base_(file_offset), record_(record) {}
  uint8_t u8(const char* field) { return static_cast<uint8_t>(le(1, field)); }
  uint16_t u16(const char* field) { return static_cast<uint16_t>(le(2, field)); }
  uint32_t u32(const char* field) { return static_cast<uint32_t>(le(4, field)); }
  uint64_t u64(const char* field) { return le(8, field); }
  std::string str(const char* field);                               // u32 length + bytes
  std::span<const std::byte> bytes(uint64_t n, const char* field);  // n bytes
  size_t remaining() const { return data_.size() - pos_; }
  uint64_t offset() const { return base_ + pos_; }  // in the file
  void fail(const char* why, const char* field);
  const std::optional<Error>& error() const { return error_; }

 private:
  uint64_t le(int n, const char* field);
  std::span<const std::byte> data_;
  size_t pos_ = 0;
  uint64_t base_;
  const char* record_;
  std::optional<Error> error_;
};

}  // namespace tlvlink::foxglove::internal
