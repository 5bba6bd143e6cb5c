#pragma once
#ifndef TLVLINK_LISTEN_PRIVATE
#error "message_copy.h is internal to tools/listen"
#endif
// A decoded message's view as the protocol's message struct (runtime/protocol messages.h), for
// the shared JSON-lines writer (runtime/stream json_lines.h), which formats structs: what a board
// writes and what the listener received go through one formatter. Each copy owns the lists its
// struct points to; the strings and numbers still point into the received payload.

#include <string_view>
#include <vector>

#include "tlvlink/protocol/messages.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::listen::internal {

struct HelloCopy {
  explicit HelloCopy(const protocol::HelloView& v);
  HelloCopy(const HelloCopy&) = delete;  // the struct points into the vectors
  HelloCopy& operator=(const HelloCopy&) = delete;

  std::vector<protocol::SensorInfo> sensors;
  std::vector<std::vector<std::string_view>> labels;
  std::vector<protocol::HeadInfo> heads;
  std::vector<std::string_view> stages;
  protocol::Hello hello;
  uint64_t schema_hash = 0;  // the board's
};

struct FrameCopy {
  explicit FrameCopy(const protocol::FramePredictionView& v);
  FrameCopy(const FrameCopy&) = delete;
  FrameCopy& operator=(const FrameCopy&) = delete;

  std::vector<protocol::HeadOutput> heads;
  protocol::FramePrediction frame;
};

struct GraspCopy {
  explicit GraspCopy(const protocol::GraspPredictionView& v);
  GraspCopy(const GraspCopy&) = delete;
  GraspCopy& operator=(const GraspCopy&) = delete;

  std::vector<protocol::GraspFrame> frames;
  protocol::GraspPrediction grasp;
};

struct StatsCopy {
  explicit StatsCopy(const protocol::StatsView& v);
  StatsCopy(const StatsCopy&) = delete;
  StatsCopy& operator=(const StatsCopy&) = delete;

  std::vector<protocol::SensorStats> sensors;
  std::vector<protocol::DropCount> drops;
  protocol::Stats stats;
};

}  // namespace tlvlink::listen::internal
