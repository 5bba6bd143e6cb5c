#include "mcap_bytes.h"

namespace tlvlink::foxglove::internal {

const char* opcode_name(uint8_t op) {
  switch (op) {
    case kHeader: return "Header";
    case kFooter: return "Footer";
    case kSchema: return "Schema";
    case kChannel: return "Channel";
    case kMessage: return "Message";
    case kChunk: return "Chunk";
    case kMessageIndex: return "MessageIndex";
    case kChunkIndex: return "ChunkIndex";
    case kAttachment: return "Attachment";
    case kAttachmentIndex: return "AttachmentIndex";
    case kStatistics: return "Statistics";
    case kMetadata: return "Metadata";
    case kMetadataIndex: return "MetadataIndex";
    case kSummaryOffset: return "SummaryOffset";
    case kDataEnd: return "DataEnd";
  }
  return "unknown";
}

void ByteReader::fail(const char* why, const char* field) {
  if (error_) return;
  error_ = Error::make(ErrorCode::kFormat, "%s record, field %s at offset %llu: %s", record_, field,
                       static_cast<unsigned long long>(offset()), why);
}

uint64_t ByteReader::le(int n, const char* field) {
  if (error_) return 0;
  if (remaining() < static_cast<size_t>(n)) {
    fail("the record ends inside it", field);
    return 0;
  }
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(data_[pos_ + i]) << (8 * i);
  pos_ += n;
  return v;
}

std::span<const std::byte> ByteReader::bytes(uint64_t n, const char* field) {
  if (error_) return {};
  if (n > remaining()) {
    error_ =
        Error::make(ErrorCode::kFormat,
                    "%s record, field %s at offset %llu: length %llu, but only %zu bytes remain",
                    record_, field, static_cast<unsigned long long>(offset()),
                    static_cast<unsigned long long>(n), remaining());
    return {};
  }
  std::span<const std::byte> out = data_.subspan(pos_, n);
  pos_ += n;
  return out;
}

std::string ByteReader::str(const char* field) {
  const uint32_t n = u32(field);
  std::span<const std::byte> b = bytes(n, field);
  return std::string(reinterpret_cast<const char*>(b.data()), b.size());
}

}  // namespace tlvlink::foxglove::internal
