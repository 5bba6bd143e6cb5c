// Pipeline records -> protocol messages: every field the mapping sets, checked after a round
// trip through the protocol's encoder and decoder (what a host sees).
#include "tlvlink/stream/message_mapper.h"

#include <array>
#include <cstddef>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::stream {
namespace {

template <typename M>
std::vector<std::byte> encoded(const M& m) {
  std::vector<std::byte> buffer(protocol::kEncodeBufferSize);
  auto payload = protocol::encode_payload(m, buffer);
  EXPECT_TRUE(payload.ok()) << payload.error().message();
  // Copied to an 8-byte aligned buffer, as the deframer hands payloads to the decoders.
  std::vector<std::byte> out(payload->size());
  std::memcpy(out.data(), payload->data(), out.size());
  return out;
}

TEST(MessageMapper, FramePredictionCarriesStagesHeadsAndContact) {
  pipeline::FramePrediction p;
  p.sensor = 1;
  p.sequence = 42;
  p.times = {1000, 1300, 2000, 2100, 2500, 4000, 4100, 0};
  p.contact_state = 2;
  p.contact_score_dn = 7.25f;
  p.encoder_ran = true;
  p.head_count = 1;
  p.heads[0].head = 3;
  p.heads[0].labels = 2;
  p.heads[0].probability[0] = 0.25f;
  p.heads[0].probability[1] = 0.75f;
  MessageMapper mapper(false);
  const protocol::FramePrediction m = mapper.frame(p);
  EXPECT_EQ(m.sensor, 1);
  EXPECT_EQ(m.frame_sequence, 42u);
  EXPECT_EQ(m.timing.capture_ns, 1000);
  EXPECT_EQ(m.timing.infer_start_ns, 2100);
  EXPECT_EQ(m.timing.infer_end_ns, 4100);
  const std::vector<uint32_t> stages(m.stage_ns.begin(), m.stage_ns.end());
  EXPECT_EQ(stages, (std::vector<uint32_t>{300, 700, 100, 400, 1500, 100}));
  EXPECT_TRUE(m.contact);
  ASSERT_EQ(m.heads.size(), 1u);
  EXPECT_EQ(m.heads[0].head, 3);
  EXPECT_EQ(m.heads[0].probabilities.size(), 2u);
  EXPECT_EQ(m.heads[0].probabilities[1], 0.75f);
  EXPECT_TRUE(m.embedding.empty());
  const auto bytes = encoded(m);
  auto view = protocol::decode_frame_prediction(bytes);
  ASSERT_TRUE(view.ok()) << view.error().message();
  EXPECT_EQ(view->frame_sequence(), 42u);
  // Protocol 1.3: the gate's state and score travel (a 1.2 host skips them).
  EXPECT_EQ(view->gate(), protocol::GateState::kContact);
  EXPECT_EQ(view->gate_score_dn(), 7.25f);
}

// pipeline::ContactState -> GateState: calibrating (no decision yet) is not "no contact".
TEST(MessageMapper, GateStateOfEveryContactState) {
  MessageMapper mapper(false);
  pipeline::FramePrediction p;
  const protocol::GateState want[] = {protocol::GateState::kCalibrating, protocol::GateState::kNone,
                                      protocol::GateState::kContact};
  for (uint8_t state = 0; state < 3; ++state) {
    p.contact_state = state;
    const protocol::FramePrediction m = mapper.frame(p);
    EXPECT_EQ(m.gate, want[state]) << int{state};
    EXPECT_EQ(m.contact, state == 2) << "contact keeps its 1.2 meaning";
    const auto bytes = encoded(m);
    EXPECT_EQ(protocol::decode_frame_prediction(bytes)->gate(), want[state]);
  }
}

TEST(MessageMapper, AGatedFrameHasNoHeadsAndUnsetStagesAreZero) {
  pipeline::FramePrediction p;
  p.times = {1000, 1300, 2000, 2100, 0, 0, 0, 0};
  p.encoder_ran = false;
  p.head_count = 2;
  MessageMapper mapper(false);
  const protocol::FramePrediction m = mapper.frame(p);
  EXPECT_TRUE(m.heads.empty());
  EXPECT_FALSE(m.contact);
  EXPECT_EQ(m.stage_ns[3], 0u);  // preprocess never ran
  EXPECT_EQ(m.stage_ns[5], 0u);
}

TEST(MessageMapper, GraspPredictionNamesPhasesAndItsSource) {
  pipeline::GraspPrediction g;
  g.grasp_id = 9;
  g.computed = false;
  g.probability = 0.9f;
  g.started_ns = 5;
  g.decided_ns = 7;
  g.frame_count = 2;
  g.frames[0] = {0, 0, 100, 11};
  g.frames[1] = {1, 1, 101, 12};
  std::strcpy(g.reason.data(), "too few frames");
  MessageMapper detected(true), commanded(false);
  const protocol::GraspPrediction m = detected.grasp(g);
  EXPECT_EQ(m.grasp_id, 9u);
  EXPECT_EQ(m.status, protocol::GraspStatus::kNotComputed);
  EXPECT_EQ(m.reason, protocol::GraspReason::kOther);
  EXPECT_EQ(m.reason_text, "too few frames");
  ASSERT_EQ(m.frames.size(), 2u);
  EXPECT_EQ(m.frames[0].phase, protocol::GraspPhase::kBefore);
  EXPECT_EQ(m.frames[1].phase, protocol::GraspPhase::kDuring);
  EXPECT_EQ(m.frames[1].capture_ns, 12);
  EXPECT_EQ(m.phase_source, protocol::PhaseSource::kDetected);
  EXPECT_EQ(m.closed_ns, 5);
  EXPECT_EQ(m.infer_end_ns, 7);
  EXPECT_EQ(commanded.grasp(g).phase_source, protocol::PhaseSource::kCommand);
}

TEST(MessageMapper, StatsHaveOneDropEntryPerCause) {
  StreamTotals t;
  t.seconds = 1.5;
  t.sensors = 2;
  t.sensor_frames = {10, 20};
  t.capture_gap = 1;
  t.capture_error = 2;
  t.inference_busy = 3;
  t.queue_full = 4;
  t.cpu_cores = 4;
  MessageMapper mapper(false);
  const protocol::Stats m = mapper.stats(t);
  EXPECT_EQ(m.uptime_ns, 1'500'000'000);
  ASSERT_EQ(m.sensors.size(), 2u);
  EXPECT_EQ(m.sensors[1].frames, 20u);
  ASSERT_EQ(m.drops.size(), 4u);
  EXPECT_EQ(m.drops[0].cause, protocol::DropCause::kCaptureGap);
  EXPECT_EQ(m.drops[3].cause, protocol::DropCause::kQueueFull);
  EXPECT_EQ(m.drops[3].count, 4u);
  EXPECT_EQ(m.cpu_cores, 4);
}

TEST(MessageMapper, EventsAreErrorReports) {
  const protocol::ErrorReport e = MessageMapper::event(true, -1, "camera gone");
  EXPECT_EQ(e.code, static_cast<uint16_t>(ErrorCode::kCapture));
  EXPECT_EQ(e.name, "error");
  EXPECT_EQ(e.sensor, protocol::kNoSensor);
  const protocol::ErrorReport i = MessageMapper::event(false, 2, "reloaded");
  EXPECT_EQ(i.code, 0);
  EXPECT_EQ(i.name, "info");
  EXPECT_EQ(i.sensor, 2);
}

}  // namespace
}  // namespace tlvlink::stream
