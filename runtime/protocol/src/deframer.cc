#include "tlvlink/protocol/deframer.h"

#include "tlvlink/protocol/cobs.h"

namespace tlvlink::protocol {

void Deframer::append(const std::byte* data, size_t n) {
  if (n == 0) return;
  // The segment excludes its delimiter: kMaxWireFrameSize - 1 bytes at most.
  if (overflow_ || n > kMaxWireFrameSize - 1 - wire_len_) {
    if (!overflow_) counters_.discarded_bytes += wire_len_;
    overflow_ = true;
    wire_len_ = 0;
    counters_.discarded_bytes += n;
    return;
  }
  std::memcpy(wire_ + wire_len_, data, n);
  wire_len_ += n;
}

ReceivedFrame Deframer::finish_segment() {
  ReceivedFrame out;
  const size_t n = wire_len_;
  wire_len_ = 0;
  if (overflow_) {
    overflow_ = false;
    ++counters_.oversized;
    out.verdict = FrameVerdict::kOversized;
    return out;
  }
  out.wire = std::span<const std::byte>(wire_, n);
  const Result<size_t> decoded = cobs_decode(out.wire, frame_);
  if (!decoded.ok()) {
    out.verdict = FrameVerdict::kCobs;
  } else if (decoded.value() > kMaxFrameSize) {
    out.verdict = FrameVerdict::kOversized;
  } else {
    out.verdict =
        check_frame(std::span<const std::byte>(frame_, decoded.value()), out.header, out.payload);
  }
  switch (out.verdict) {
    case FrameVerdict::kOk: ++counters_.frames; return out;
    case FrameVerdict::kOversized: ++counters_.oversized; break;
    case FrameVerdict::kCobs: ++counters_.cobs; break;
    case FrameVerdict::kTruncated: ++counters_.truncated; break;
    case FrameVerdict::kCrc: ++counters_.crc; break;
    case FrameVerdict::kMagic: ++counters_.magic; break;
    case FrameVerdict::kVersion: ++counters_.version; break;
    case FrameVerdict::kLength: ++counters_.length; break;
    case FrameVerdict::kUnsupportedFlags: ++counters_.flags; break;
  }
  counters_.discarded_bytes += n;
  return out;
}

}  // namespace tlvlink::protocol
