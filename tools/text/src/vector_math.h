#pragma once
#ifndef TLVLINK_TEXT_PRIVATE
#error "vector_math.h is internal to tools/text: include its public headers instead"
#endif
// Small helpers shared by the text encoders: L2 normalisation with a finite, non-zero check.

#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::text::internal {

// Scales `v` to unit length; an error (naming `what`) when it is zero or not finite.
inline Status normalise_in_place(std::span<float> v, const std::string& what) {
  double sum = 0;
  for (float x : v) sum += static_cast<double>(x) * static_cast<double>(x);
  if (!std::isfinite(sum)) {
    return Error::make(ErrorCode::kNonFiniteValue, "%s: embedding has NaN/Inf values",
                       what.c_str());
  }
  if (sum <= 0) {
    return Error::make(ErrorCode::kInvalidArgument, "%s: embedding is all zeros", what.c_str());
  }
  const double inv = 1.0 / std::sqrt(sum);
  for (float& x : v) x = static_cast<float>(static_cast<double>(x) * inv);
  return {};
}

}  // namespace tlvlink::text::internal
