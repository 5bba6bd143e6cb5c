#pragma once
// One fully populated instance of every stream message (each field away from its default), for
// round-trip, allocation and evolution tests. The data lives in static storage.

#include "tlvlink/protocol/messages.h"

namespace tlvlink::testing {

protocol::Hello sample_hello();
protocol::FramePrediction sample_frame_prediction(bool with_embedding);
protocol::GraspPrediction sample_grasp_prediction();
protocol::GraspPrediction sample_grasp_not_computed();
protocol::Stats sample_stats();
protocol::ErrorReport sample_error();
protocol::Ack sample_ack();
protocol::Nack sample_nack();
protocol::Pong sample_pong();
protocol::FrameImage sample_frame_image();  // a 32x24 mask and a 4 KiB stand-in JPEG
protocol::Command sample_command();

}  // namespace tlvlink::testing
