#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "check.h is internal to tools/sim: include its public headers instead"
#endif
// Named range checks for parameter validation: every error names the field and its value, and
// a NaN or Inf is reported as "not finite" before any range test (NaN compares false).

#include <cmath>
#include <cstdint>

#include "tlvlink/error.h"

namespace tlvlink::sim::internal {

inline Status check_finite(const char* field, double value) {
  if (!std::isfinite(value)) {
    return Error::make(ErrorCode::kInvalidArgument, "%s = %g is not finite", field, value);
  }
  return {};
}

inline Status check_range(const char* field, double value, double lo, double hi) {
  TLV_TRY(check_finite(field, value));
  if (value < lo || value > hi) {
    return Error::make(ErrorCode::kInvalidArgument, "%s = %g is outside [%g, %g]", field, value, lo,
                       hi);
  }
  return {};
}

inline Status check_int_range(const char* field, int64_t value, int64_t lo, int64_t hi) {
  if (value < lo || value > hi) {
    return Error::make(ErrorCode::kInvalidArgument, "%s = %lld is outside [%lld, %lld]", field,
                       static_cast<long long>(value), static_cast<long long>(lo),
                       static_cast<long long>(hi));
  }
  return {};
}

}  // namespace tlvlink::sim::internal
