#pragma once
// Internals of tlvlink_protocol: the fixed-buffer flatbuffers allocator, the pre-build size bound
// and the generated schema code. Not part of the public API.
#ifndef TLVLINK_PROTOCOL_PRIVATE
#error "protocol_internal.h is internal to tlvlink_protocol: include tlvlink/protocol/*.h instead"
#endif

#include <flatbuffers/flatbuffers.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string_view>

#include "stream_generated.h"
#include "tlvlink/error.h"
#include "tlvlink/protocol/encode.h"

namespace tlvlink::protocol::internal {

// Hands out the one caller buffer and never grows. The builder is created with the whole buffer
// as its initial size and the message's SizeBound is checked against it first, so a second
// allocation cannot happen; if one were ever asked for, the bound is wrong: abort rather than
// write outside the buffer.
class FixedAllocator final : public flatbuffers::Allocator {
 public:
  explicit FixedAllocator(std::span<std::byte> buffer) : buffer_(buffer) {}
  uint8_t* allocate(size_t size) override {
    if (size > buffer_.size() || handed_out_) std::abort();
    handed_out_ = true;
    return reinterpret_cast<uint8_t*>(buffer_.data());
  }
  void deallocate(uint8_t*, size_t) override { handed_out_ = false; }
  uint8_t* reallocate_downward(uint8_t*, size_t, size_t, size_t, size_t) override { std::abort(); }

 private:
  std::span<std::byte> buffer_;
  bool handed_out_ = false;
};

// A generous upper bound on the bytes (data + builder scratch) a message needs while it is
// built: every field counted at 8 bytes plus alignment, vtables, scratch field records.
struct SizeBound {
  size_t bytes = 64;  // root offset, final alignment
  void table(size_t fields) { bytes += 16 + 2 * fields + 16 * fields + 8; }
  void string(std::string_view s) { bytes += s.size() + 16; }
  void vector(size_t n, size_t element_size) { bytes += n * element_size + 16; }
};

// Builds one payload inside `buffer` after checking `bound`. `build(fbb)` returns the root
// table's offset; the finished payload is returned as a subspan of `buffer`.
template <typename Build>
Result<std::span<const std::byte>> build_payload(const char* what, const SizeBound& bound,
                                                 std::span<std::byte> buffer, Build&& build) {
  TLV_ENSURE(reinterpret_cast<uintptr_t>(buffer.data()) % 8 == 0, ErrorCode::kInvalidArgument,
             "encoding %s: the buffer must be 8-byte aligned", what);
  const size_t capacity = buffer.size() & ~size_t{7};
  TLV_ENSURE(bound.bytes <= capacity, ErrorCode::kProtocolTooLarge,
             "encoding %s: the message may need up to %zu bytes to build; the buffer has %zu", what,
             bound.bytes, capacity);
  FixedAllocator allocator(buffer.first(capacity));
  flatbuffers::FlatBufferBuilder fbb(capacity, &allocator, false, 8);
  const auto root = build(fbb);
  fbb.Finish(root);
  const size_t size = fbb.GetSize();
  TLV_ENSURE(size <= kMaxPayloadSize, ErrorCode::kProtocolTooLarge,
             "encoding %s: the payload is %zu bytes, the protocol allows %zu", what, size,
             kMaxPayloadSize);
  const auto* data = reinterpret_cast<const std::byte*>(fbb.GetBufferPointer());
  // The builder returns the buffer to the allocator when it goes out of scope; the bytes stay.
  return std::span<const std::byte>(data, size);
}

inline flatbuffers::Offset<flatbuffers::String> string_or_null(flatbuffers::FlatBufferBuilder& fbb,
                                                               std::string_view s) {
  return s.empty() ? 0 : fbb.CreateString(s.data(), s.size());
}

// A vector of strings, or null when empty. Offsets are staged in a fixed array (kMaxListLength).
flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<flatbuffers::String>>> string_list(
    flatbuffers::FlatBufferBuilder& fbb, std::span<const std::string_view> strings);

Status check_list(const char* what, const char* field, size_t n);

// Verifies `payload` as a root table of type T (bounded depth and table count).
template <typename T>
Result<const T*> verified_root(const char* what, std::span<const std::byte> payload) {
  constexpr flatbuffers::uoffset_t kMaxDepth = 16;
  constexpr flatbuffers::uoffset_t kMaxTables = 4096;
  const auto* bytes = reinterpret_cast<const uint8_t*>(payload.data());
  TLV_ENSURE(reinterpret_cast<uintptr_t>(bytes) % 4 == 0, ErrorCode::kInvalidArgument,
             "decoding %s: the payload must be 4-byte aligned", what);
  flatbuffers::Verifier verifier(bytes, payload.size(), kMaxDepth, kMaxTables);
  TLV_ENSURE(payload.size() >= sizeof(flatbuffers::uoffset_t) && verifier.VerifyBuffer<T>(nullptr),
             ErrorCode::kProtocolMalformed, "%s payload of %zu bytes does not verify", what,
             payload.size());
  return flatbuffers::GetRoot<T>(bytes);
}

inline std::string_view view(const flatbuffers::String* s) {
  return s ? std::string_view(s->c_str(), s->size()) : std::string_view();
}

}  // namespace tlvlink::protocol::internal
