#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "session_names.h is internal to tools/sim: include its public headers instead"
#endif
// Names of generated sessions and objects: unique within a dataset, deterministic, and in the
// real datasets' shapes (Touch-and-Go sessions are "YYYYMMDD_HHMMSS" recording start times).

#include <cstdint>
#include <string>

#include "tlvlink/sim/dataset.h"
#include "tlvlink/sim/renderer.h"

namespace tlvlink::sim::internal {

// Session `session` of the dataset seeded `seed`: a start time that grows with the session
// index (10-minute slots with a seeded minute/second inside each), from a seeded day of 2022.
std::string session_name(uint64_t seed, int64_t session);

// "<class name with '_'>_<object index, 4+ digits>", e.g. "natural_fabric_0042".
std::string object_name(int32_t class_id, int64_t object_index);

// Copies a rendered frame's pixels into a dataset image (reusing its buffer).
inline void copy_frame(const Frame& frame, RgbImage& out) {
  out.height = frame.height;
  out.width = frame.width;
  out.rgb.assign(frame.rgb.begin(), frame.rgb.end());
}

}  // namespace tlvlink::sim::internal
