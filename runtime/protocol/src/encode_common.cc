#include <array>

#include "protocol_internal.h"

namespace tlvlink::protocol::internal {

flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<flatbuffers::String>>> string_list(
    flatbuffers::FlatBufferBuilder& fbb, std::span<const std::string_view> strings) {
  if (strings.empty()) return 0;
  std::array<flatbuffers::Offset<flatbuffers::String>, kMaxListLength> offsets;
  for (size_t i = 0; i < strings.size(); ++i) {
    offsets[i] = fbb.CreateString(strings[i].data(), strings[i].size());
  }
  return fbb.CreateVector(offsets.data(), strings.size());
}

Status check_list(const char* what, const char* field, size_t n) {
  TLV_ENSURE(n <= kMaxListLength, ErrorCode::kInvalidArgument,
             "encoding %s: %s has %zu entries, at most %zu are allowed", what, field, n,
             kMaxListLength);
  return Status();
}

}  // namespace tlvlink::protocol::internal
