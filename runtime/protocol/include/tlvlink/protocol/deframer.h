#pragma once
// Receiving side of the frame layer: bytes in (any chunking), one callback per delimited
// segment out, with the verdict and, for good frames, the header and payload. Resynchronises on
// the next 0x00 after any damage. Fixed buffers inside (about 33 KB): no allocation, no I/O.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "tlvlink/protocol/frame.h"
#include "tlvlink/protocol/wire.h"

namespace tlvlink::protocol {

struct DeframerCounters {
  uint64_t bytes = 0;   // bytes fed
  uint64_t frames = 0;  // good frames
  uint64_t oversized = 0, cobs = 0, truncated = 0, crc = 0, magic = 0, version = 0, length = 0,
           flags = 0;            // rejected segments by verdict
  uint64_t discarded_bytes = 0;  // bytes of rejected segments
  uint64_t rejected() const {
    return oversized + cobs + truncated + crc + magic + version + length + flags;
  }
};

struct ReceivedFrame {
  FrameVerdict verdict = FrameVerdict::kOk;
  FrameHeader header;                  // see check_frame() for when it is set
  std::span<const std::byte> payload;  // kOk only: 8-byte aligned, valid until the next feed()
  std::span<const std::byte>
      wire;  // the segment as received, without delimiter; empty when oversized
};

class Deframer {
 public:
  Deframer() = default;
  Deframer(const Deframer&) = delete;
  Deframer& operator=(const Deframer&) = delete;

  // Calls on_frame(const ReceivedFrame&) for every non-empty segment completed by `bytes`.
  template <typename OnFrame>
  void feed(std::span<const std::byte> bytes, OnFrame&& on_frame);

  // Forgets a partly received segment (after a reconnect); it is not counted.
  void reset() { wire_len_ = 0, overflow_ = false; }
  const DeframerCounters& counters() const { return counters_; }

 private:
  void append(const std::byte* data, size_t n);
  ReceivedFrame finish_segment();

  alignas(8) std::byte wire_[kMaxWireFrameSize];
  alignas(8) std::byte frame_[kMaxWireFrameSize];
  size_t wire_len_ = 0;
  bool overflow_ = false;
  DeframerCounters counters_;
};

template <typename OnFrame>
void Deframer::feed(std::span<const std::byte> bytes, OnFrame&& on_frame) {
  counters_.bytes += bytes.size();
  const std::byte* p = bytes.data();
  const std::byte* const end = p + bytes.size();
  while (p < end) {
    const void* zero = std::memchr(p, 0, static_cast<size_t>(end - p));
    const std::byte* stop = zero ? static_cast<const std::byte*>(zero) : end;
    append(p, static_cast<size_t>(stop - p));
    p = stop;
    if (zero == nullptr) break;
    ++p;
    if (wire_len_ > 0 || overflow_) {
      const ReceivedFrame frame = finish_segment();
      on_frame(frame);
    }
  }
}

}  // namespace tlvlink::protocol
