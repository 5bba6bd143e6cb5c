#include "tlvlink/protocol/cobs.h"

#include <cstring>

namespace tlvlink::protocol {

CobsEncoder::CobsEncoder(std::span<std::byte> out) : out_(out) { overflow_ = out.empty(); }

void CobsEncoder::emit(std::byte b) {
  if (pos_ >= out_.size()) {
    overflow_ = true;
    return;
  }
  out_[pos_++] = b;
}

// Closes the current run: its code byte goes where code_pos_ reserved it, and the next code
// byte's place is reserved. code_pos_ is always inside out_ unless overflow_ is set.
void CobsEncoder::close_run(uint8_t code) {
  out_[code_pos_] = std::byte{code};
  code_pos_ = pos_;
  emit(std::byte{0});
  code_ = 1;
}

// A run of up to 254 non-zero bytes follows each code byte; code = run length + 1. A run of 254
// (code 0xFF) is not followed by an implied zero. The last code byte is written by finish(), and
// a full run at the very end needs no extra code byte.
void CobsEncoder::put(std::span<const std::byte> bytes) {
  for (std::byte b : bytes) {
    if (overflow_) return;
    if (code_ == 0xFF) close_run(0xFF);  // the previous run is full and more data follows
    if (overflow_) return;
    if (b == std::byte{0}) {
      close_run(code_);
    } else {
      emit(b);
      ++code_;
    }
  }
}

Result<size_t> CobsEncoder::finish() {
  TLV_ENSURE(!overflow_, ErrorCode::kProtocolTooLarge,
             "COBS encoding does not fit its %zu-byte output buffer", out_.size());
  out_[code_pos_] = std::byte{code_};
  return pos_;
}

Result<size_t> cobs_decode(std::span<const std::byte> in, std::span<std::byte> out) {
  size_t i = 0, o = 0;
  while (i < in.size()) {
    const size_t code = static_cast<uint8_t>(in[i++]);
    TLV_ENSURE(code != 0, ErrorCode::kProtocolMalformed, "COBS: zero byte inside a frame at %zu",
               i - 1);
    const size_t run = code - 1;
    TLV_ENSURE(run <= in.size() - i, ErrorCode::kProtocolMalformed,
               "COBS: code byte at %zu runs %zu bytes past the end of the frame", i - 1,
               run - (in.size() - i));
    TLV_ENSURE(run <= out.size() - o, ErrorCode::kProtocolTooLarge,
               "COBS: decoded frame larger than its %zu-byte buffer", out.size());
    TLV_ENSURE(std::memchr(in.data() + i, 0, run) == nullptr, ErrorCode::kProtocolMalformed,
               "COBS: zero byte inside a frame after %zu", i);
    std::memcpy(out.data() + o, in.data() + i, run);
    i += run, o += run;
    if (code != 0xFF && i < in.size()) {
      TLV_ENSURE(o < out.size(), ErrorCode::kProtocolTooLarge,
                 "COBS: decoded frame larger than its %zu-byte buffer", out.size());
      out[o++] = std::byte{0};
    }
  }
  return o;
}

}  // namespace tlvlink::protocol
