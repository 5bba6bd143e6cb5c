#pragma once
// Messages with content derived from a number, so a receiver can check every field of what it
// got (the corruption, reconnect and benchmark tests), and a Hello.

#include <array>
#include <cstdint>
#include <span>

#include "tlvlink/protocol/messages.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::testing {

protocol::Hello fixture_hello();

// A FramePrediction for frame `n` of sensor n % 2: two heads (4 and 2 labels) and, if asked, a
// 32-float embedding, every value a function of n. `storage` must outlive the message.
struct PredictionStorage {
  std::array<float, 4> material{};
  std::array<float, 2> hardness{};
  std::array<protocol::HeadOutput, 2> heads{};
  std::array<uint32_t, 5> stages{};
  std::array<float, 32> embedding{};
};
protocol::FramePrediction fixture_prediction(uint32_t n, PredictionStorage& storage,
                                             bool with_embedding = false, int64_t capture_ns = 0);
// True when every field of `v` is what fixture_prediction(v.frame_sequence()) has.
bool fixture_prediction_intact(const protocol::FramePredictionView& v);

}  // namespace tlvlink::testing
