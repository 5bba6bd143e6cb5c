#pragma once
// Consistent Overhead Byte Stuffing (Cheshire & Baker): the encoding has no 0x00 byte, so 0x00
// can delimit frames. CobsEncoder writes into a caller's buffer from any number of pieces;
// cobs_decode undoes it. Neither allocates.

#include <cstddef>
#include <cstdint>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/protocol/wire.h"

namespace tlvlink::protocol {

class CobsEncoder {
 public:
  // `out` must hold cobs_max_encoded_size(total bytes put); put() past the end sets overflow.
  explicit CobsEncoder(std::span<std::byte> out);
  void put(std::span<const std::byte> bytes);
  // Writes the last code byte; returns the encoded length (no delimiter), or an error if `out`
  // was too small.
  Result<size_t> finish();

 private:
  void emit(std::byte b);
  void close_run(uint8_t code);
  std::span<std::byte> out_;
  size_t pos_ = 1, code_pos_ = 0;
  uint8_t code_ = 1;
  bool overflow_ = false;
};

// Decodes `in` (one frame, no delimiter, no 0x00 inside) into `out`; returns the decoded length.
// The decoded length is at most in.size(). Fails on a code byte that runs past the end of `in`
// or on a result larger than `out`.
Result<size_t> cobs_decode(std::span<const std::byte> in, std::span<std::byte> out);

}  // namespace tlvlink::protocol
