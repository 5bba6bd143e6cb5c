// The per-message path allocates nothing: encode every message type, frame it, deframe it and
// decode it while counting heap allocations (STYLE: setup allocates, the frame loop does not).
#include <gtest/gtest.h>

#include <vector>

#include "protocol/message_samples.h"
#include "support/alloc_counter.h"
#include "tlvlink/protocol/clock.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {

using namespace tlvlink::testing;

alignas(8) std::byte g_scratch[kEncodeBufferSize];
std::byte g_wire[kMaxWireFrameSize];

template <typename M>
size_t send(const M& m, Deframer& d, uint32_t seq) {
  FrameHeader h;
  h.sequence = seq;
  Result<size_t> n = encode_message(m, h, g_scratch, g_wire);
  if (!n.ok()) return 0;
  size_t good = 0;
  d.feed(std::span<const std::byte>(g_wire, n.value()), [&](const ReceivedFrame& f) {
    if (f.verdict == FrameVerdict::kOk && verify_payload(f.header.type, f.payload).ok()) ++good;
  });
  return good;
}

TEST(ProtocolAllocation, EncodeFrameDeframeDecodeAllocateNothing) {
  static Deframer deframer;  // 33 KB: built once, like a receiver at setup
  const Hello hello = sample_hello();
  const FramePrediction frame = sample_frame_prediction(true);
  const GraspPrediction grasp = sample_grasp_prediction();
  const Stats stats = sample_stats();
  ClockSync clock;
  size_t good = 0;
  start_counting_allocations();
  for (uint32_t i = 0; i < 100; ++i) {
    good += send(hello, deframer, i);
    good += send(frame, deframer, i);
    good += send(grasp, deframer, i);
    good += send(stats, deframer, i);
    good += send(sample_error(), deframer, i);
    good += send(sample_ack(), deframer, i);
    good += send(sample_nack(), deframer, i);
    good += send(sample_pong(), deframer, i);
    good += send(sample_frame_image(), deframer, i);
    good += send(sample_command(), deframer, i);
    Result<FramePredictionView> v = decode_frame_prediction(std::span<const std::byte>());
    (void)v;
    clock.add({i, i + 5, i + 6, i + 10});
  }
  const size_t allocations = stop_counting_allocations();
  EXPECT_EQ(good, 1000u);
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace tlvlink::protocol
