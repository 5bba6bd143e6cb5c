#include "byte_faults.h"

namespace tlvlink::testing {

size_t ByteFaults::apply(std::span<const std::byte> in, std::byte* out) {
  size_t n = 0;
  for (std::byte b : in) {
    ++counts_.bytes;
    const double r = uniform_(rng_);
    if (r < rates_.byte_drop_rate) {
      ++counts_.dropped;
      continue;
    }
    if (r < rates_.byte_drop_rate + rates_.byte_error_rate) {
      b ^= static_cast<std::byte>(other_(rng_));  // XOR with 1..255: always a different byte
      ++counts_.corrupted;
    }
    out[n++] = b;
  }
  return n;
}

}  // namespace tlvlink::testing
