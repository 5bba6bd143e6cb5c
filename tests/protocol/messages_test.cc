// Every message type: encode -> frame -> deframe -> decode gives back every field; malformed
// payloads are refused; size limits are enforced before anything is built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "protocol/message_samples.h"
#include "support/random.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {

using namespace tlvlink::testing;

// Owns an encoded payload copied out of the scratch buffer (8-byte aligned storage).
struct Encoded {
  std::vector<uint64_t> storage;
  size_t size = 0;
  std::span<const std::byte> bytes() const {
    return {reinterpret_cast<const std::byte*>(storage.data()), size};
  }
};

template <typename M>
Encoded encode(const M& m) {
  alignas(8) static std::byte scratch[kEncodeBufferSize];
  Result<std::span<const std::byte>> p = encode_payload(m, scratch);
  EXPECT_TRUE(p.ok()) << p.error().message();
  Encoded e;
  if (!p.ok()) return e;
  e.size = p.value().size();
  e.storage.resize((e.size + 7) / 8);
  std::memcpy(e.storage.data(), p.value().data(), e.size);
  return e;
}

TEST(Messages, HelloRoundTrip) {
  const Hello in = sample_hello();
  const Encoded e = encode(in);
  Result<HelloView> r = decode_hello(e.bytes());
  ASSERT_TRUE(r.ok()) << r.error().message();
  const HelloView& h = r.value();
  EXPECT_EQ(h.device(), in.device);
  EXPECT_EQ(h.board(), in.board);
  EXPECT_EQ(h.firmware_version(), in.firmware_version);
  EXPECT_EQ(h.boot_id(), in.boot_id);
  EXPECT_EQ(h.schema_hash(), schema_hash());
  EXPECT_EQ(h.model_id(), in.model_id);
  EXPECT_EQ(h.model_checksum(), in.model_checksum);
  ASSERT_EQ(h.sensor_count(), in.sensors.size());
  for (size_t i = 0; i < in.sensors.size(); ++i) {
    const SensorInfo s = h.sensor(i);
    EXPECT_EQ(s.index, in.sensors[i].index);
    EXPECT_EQ(s.name, in.sensors[i].name);
    EXPECT_EQ(s.model, in.sensors[i].model);
    EXPECT_EQ(s.serial, in.sensors[i].serial);
    EXPECT_EQ(s.pixel_format, in.sensors[i].pixel_format);
    EXPECT_EQ(s.width, in.sensors[i].width);
    EXPECT_EQ(s.height, in.sensors[i].height);
    EXPECT_EQ(s.fps, in.sensors[i].fps);
  }
  ASSERT_EQ(h.head_count(), in.heads.size());
  for (size_t i = 0; i < in.heads.size(); ++i) {
    const HeadInfoView v = h.head(i);
    EXPECT_EQ(v.name(), in.heads[i].name);
    EXPECT_EQ(v.kind(), in.heads[i].kind);
    ASSERT_EQ(v.label_count(), in.heads[i].labels.size());
    for (size_t k = 0; k < v.label_count(); ++k) EXPECT_EQ(v.label(k), in.heads[i].labels[k]);
    if (std::isnan(in.heads[i].accuracy)) {
      EXPECT_TRUE(std::isnan(v.accuracy()));
      EXPECT_TRUE(std::isnan(v.majority_rate()));
    } else {
      EXPECT_EQ(v.accuracy(), in.heads[i].accuracy);
      EXPECT_EQ(v.majority_rate(), in.heads[i].majority_rate);
    }
    // Minor 1's cross-validated record: NaN in, NaN out.
    const auto same = [](float got, float want) {
      return std::isnan(want) ? std::isnan(got) : got == want;
    };
    EXPECT_TRUE(same(v.accuracy_ci_low(), in.heads[i].accuracy_ci_low)) << i;
    EXPECT_TRUE(same(v.accuracy_ci_high(), in.heads[i].accuracy_ci_high)) << i;
    EXPECT_TRUE(same(v.balanced_accuracy(), in.heads[i].balanced_accuracy)) << i;
    EXPECT_TRUE(same(v.baseline_accuracy(), in.heads[i].baseline_accuracy)) << i;
    EXPECT_EQ(v.groups(), in.heads[i].groups);
  }
  ASSERT_EQ(h.stage_name_count(), in.stage_names.size());
  for (size_t i = 0; i < in.stage_names.size(); ++i) EXPECT_EQ(h.stage_name(i), in.stage_names[i]);
  EXPECT_EQ(h.embedding_dim(), in.embedding_dim);
  EXPECT_EQ(h.clock(), in.clock);
  EXPECT_EQ(h.max_frame_size(), in.max_frame_size);
}

TEST(Messages, FramePredictionRoundTrip) {
  for (bool with_embedding : {false, true}) {
    const FramePrediction in = sample_frame_prediction(with_embedding);
    const Encoded e = encode(in);
    Result<FramePredictionView> r = decode_frame_prediction(e.bytes());
    ASSERT_TRUE(r.ok()) << r.error().message();
    const FramePredictionView& f = r.value();
    EXPECT_EQ(f.sensor(), in.sensor);
    EXPECT_EQ(f.frame_sequence(), in.frame_sequence);
    EXPECT_EQ(f.timing().capture_ns, in.timing.capture_ns);
    EXPECT_EQ(f.timing().infer_start_ns, in.timing.infer_start_ns);
    EXPECT_EQ(f.timing().infer_end_ns, in.timing.infer_end_ns);
    EXPECT_TRUE(std::equal(f.stage_ns().begin(), f.stage_ns().end(), in.stage_ns.begin(),
                           in.stage_ns.end()));
    EXPECT_EQ(f.contact(), in.contact);
    ASSERT_EQ(f.head_count(), in.heads.size());
    for (size_t i = 0; i < in.heads.size(); ++i) {
      EXPECT_EQ(f.head(i).head, in.heads[i].head);
      const auto p = f.head(i).probabilities;
      EXPECT_TRUE(std::equal(p.begin(), p.end(), in.heads[i].probabilities.begin(),
                             in.heads[i].probabilities.end()));
    }
    EXPECT_TRUE(std::equal(f.embedding().begin(), f.embedding().end(), in.embedding.begin(),
                           in.embedding.end()));
    EXPECT_EQ(f.embedding().size(), with_embedding ? 64u : 0u);
  }
}

TEST(Messages, GraspPredictionRoundTrip) {
  const GraspPrediction in = sample_grasp_prediction();
  const Encoded e = encode(in);
  Result<GraspPredictionView> r = decode_grasp_prediction(e.bytes());
  ASSERT_TRUE(r.ok()) << r.error().message();
  const GraspPredictionView& g = r.value();
  EXPECT_EQ(g.grasp_id(), in.grasp_id);
  EXPECT_EQ(g.status(), GraspStatus::kComputed);
  EXPECT_EQ(g.probability(), in.probability);
  EXPECT_EQ(g.reason(), GraspReason::kNone);
  ASSERT_EQ(g.frame_count(), in.frames.size());
  for (size_t i = 0; i < in.frames.size(); ++i) {
    EXPECT_EQ(g.frame(i).sensor, in.frames[i].sensor);
    EXPECT_EQ(g.frame(i).phase, in.frames[i].phase);
    EXPECT_EQ(g.frame(i).frame_sequence, in.frames[i].frame_sequence);
    EXPECT_EQ(g.frame(i).capture_ns, in.frames[i].capture_ns);
  }
  EXPECT_EQ(g.phase_source(), PhaseSource::kDetected);
  EXPECT_EQ(g.closed_ns(), in.closed_ns);
  EXPECT_EQ(g.lifting_ns(), in.lifting_ns);
  EXPECT_EQ(g.infer_end_ns(), in.infer_end_ns);
}

TEST(Messages, NotComputedGraspCarriesNoProbability) {
  const GraspPrediction in = sample_grasp_not_computed();
  const Encoded e = encode(in);
  Result<GraspPredictionView> r = decode_grasp_prediction(e.bytes());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().status(), GraspStatus::kNotComputed);
  EXPECT_TRUE(std::isnan(r.value().probability()))
      << "a not-computed grasp must not carry a made-up value";
  EXPECT_EQ(r.value().reason(), GraspReason::kMissingFinger);
  EXPECT_EQ(r.value().reason_text(), in.reason_text);
  EXPECT_EQ(r.value().frame_count(), 0u);
}

TEST(Messages, StatsRoundTrip) {
  const Stats in = sample_stats();
  const Encoded e = encode(in);
  Result<StatsView> r = decode_stats(e.bytes());
  ASSERT_TRUE(r.ok()) << r.error().message();
  const StatsView& s = r.value();
  EXPECT_EQ(s.uptime_ns(), in.uptime_ns);
  ASSERT_EQ(s.sensor_count(), in.sensors.size());
  for (size_t i = 0; i < in.sensors.size(); ++i) {
    EXPECT_EQ(s.sensor(i).sensor, in.sensors[i].sensor);
    EXPECT_EQ(s.sensor(i).fps, in.sensors[i].fps);
    EXPECT_EQ(s.sensor(i).frames, in.sensors[i].frames);
    EXPECT_EQ(s.sensor(i).inferred, in.sensors[i].inferred);
    EXPECT_EQ(s.sensor(i).gated, in.sensors[i].gated);
  }
  ASSERT_EQ(s.drop_count(), in.drops.size());
  for (size_t i = 0; i < in.drops.size(); ++i) {
    EXPECT_EQ(s.drop(i).cause, in.drops[i].cause);
    EXPECT_EQ(s.drop(i).count, in.drops[i].count);
    EXPECT_EQ(s.drop(i).sensor, in.drops[i].sensor);
  }
  EXPECT_EQ(s.cpu_percent(), in.cpu_percent);
  EXPECT_EQ(s.cpu_cores(), in.cpu_cores);
  EXPECT_EQ(s.rss_bytes(), in.rss_bytes);
  const LinkStats l = s.link();
  EXPECT_EQ(l.link_up, in.link.link_up);
  EXPECT_EQ(l.reconnects, in.link.reconnects);
  EXPECT_EQ(l.frames_sent, in.link.frames_sent);
  EXPECT_EQ(l.bytes_sent, in.link.bytes_sent);
  EXPECT_EQ(l.frames_received, in.link.frames_received);
  EXPECT_EQ(l.frames_rejected, in.link.frames_rejected);
  EXPECT_EQ(l.queue_messages, in.link.queue_messages);
  EXPECT_EQ(l.queue_bytes, in.link.queue_bytes);
  EXPECT_EQ(l.queue_capacity_bytes, in.link.queue_capacity_bytes);
}

TEST(Messages, RepliesAndCommandRoundTrip) {
  {
    const ErrorReport in = sample_error();
    const Encoded e = encode(in);  // the decoded views point into it
    Result<ErrorReport> r = decode_error_report(e.bytes());
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.value().code, in.code);
    EXPECT_EQ(r.value().name, in.name);
    EXPECT_EQ(r.value().text, in.text);
    EXPECT_EQ(r.value().sensor, in.sensor);
  }
  {
    const Encoded e = encode(sample_ack());
    Result<Ack> r = decode_ack(e.bytes());
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.value().command_sequence, 41u);
    EXPECT_EQ(r.value().kind, CommandKind::kStart);
  }
  {
    const Nack in = sample_nack();
    const Encoded e = encode(in);
    Result<Nack> r = decode_nack(e.bytes());
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.value().command_sequence, in.command_sequence);
    EXPECT_EQ(r.value().kind, in.kind);
    EXPECT_EQ(r.value().code, in.code);
    EXPECT_EQ(r.value().text, in.text);
  }
  {
    const Pong in = sample_pong();
    const Encoded e = encode(in);
    Result<Pong> r = decode_pong(e.bytes());
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.value().command_sequence, in.command_sequence);
    EXPECT_EQ(r.value().host_send_ns, in.host_send_ns);
    EXPECT_EQ(r.value().board_receive_ns, in.board_receive_ns);
  }
  {
    const Command in = sample_command();
    const Encoded e = encode(in);
    Result<Command> r = decode_command(e.bytes());
    ASSERT_TRUE(r.ok());
    const Command& c = r.value();
    EXPECT_EQ(c.kind, in.kind);
    EXPECT_EQ(c.sensor, in.sensor);
    EXPECT_EQ(c.grasp_id, in.grasp_id);
    EXPECT_EQ(c.event_ns, in.event_ns);
    EXPECT_EQ(c.key, in.key);
    EXPECT_EQ(c.value, in.value);
    EXPECT_EQ(c.clock_offset_ns, in.clock_offset_ns);
    EXPECT_EQ(c.clock_uncertainty_ns, in.clock_uncertainty_ns);
  }
}

TEST(Messages, ThroughFramesAndDeframer) {
  alignas(8) static std::byte scratch[kEncodeBufferSize];
  std::vector<std::byte> stream, wire(kMaxWireFrameSize);
  FrameHeader h;
  h.sequence = 5;
  Result<size_t> n = encode_message(sample_frame_prediction(true), h, scratch, wire);
  ASSERT_TRUE(n.ok());
  Deframer d;
  int got = 0;
  d.feed(std::span(wire).first(n.value()), [&](const ReceivedFrame& f) {
    ASSERT_EQ(f.verdict, FrameVerdict::kOk);
    EXPECT_EQ(f.header.type, MessageType::kFramePrediction);
    EXPECT_TRUE(verify_payload(f.header.type, f.payload).ok());
    Result<FramePredictionView> v = decode_frame_prediction(f.payload);
    ASSERT_TRUE(v.ok());
    EXPECT_EQ(v.value().frame_sequence(), 4'000'000'001u);
    ++got;
  });
  EXPECT_EQ(got, 1);
}

TEST(Messages, EveryTruncationOfAPayloadIsRefused) {
  // The builder writes the first-built string last in memory, possibly followed by up to 7
  // alignment bytes: cutting only those leaves a complete, equal message.
  constexpr size_t kTrailingPadding = 7;
  const Encoded e = encode(sample_hello());
  for (size_t n = 0; n < e.size; ++n) {
    Result<HelloView> r = decode_hello(e.bytes().first(n));
    if (!r.ok()) continue;
    EXPECT_GE(n + kTrailingPadding, e.size) << n << " of " << e.size << " bytes verified";
    EXPECT_EQ(r.value().device(), sample_hello().device);
  }
}

TEST(Messages, RandomDamageNeverCrashesTheDecoder) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  const Encoded e = encode(sample_stats());
  size_t refused = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    Encoded d = e;
    auto* bytes = reinterpret_cast<std::byte*>(d.storage.data());
    for (int k = rng.int_in(1, 4); k > 0; --k)
      bytes[rng.int_in(0, static_cast<int>(d.size) - 1)] = std::byte(rng.int_in(0, 255));
    Result<StatsView> r = decode_stats(d.bytes());
    if (!r.ok()) {
      ++refused;
      continue;
    }
    // A payload that verifies is safe to read in full.
    for (size_t i = 0; i < r.value().sensor_count(); ++i) (void)r.value().sensor(i);
    for (size_t i = 0; i < r.value().drop_count(); ++i) (void)r.value().drop(i);
    (void)r.value().link();
  }
  EXPECT_GT(refused, 0u);
}

TEST(Messages, SizeLimitsAreCheckedBeforeBuilding) {
  alignas(8) static std::byte scratch[kEncodeBufferSize];
  std::vector<float> huge(kMaxPayloadSize / 4 + 10, 0.5f);
  FramePrediction f = sample_frame_prediction(false);
  f.embedding = huge;
  Result<std::span<const std::byte>> r = encode_payload(f, scratch);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kProtocolTooLarge);
  // The largest embedding that fits the protocol's limit is accepted.
  f.embedding = std::span(huge).first(2048);
  EXPECT_TRUE(encode_payload(f, scratch).ok());
  // A small buffer is refused with the sizes named, not overrun.
  alignas(8) std::byte small[64];
  Result<std::span<const std::byte>> small_result = encode_payload(sample_hello(), small);
  ASSERT_FALSE(small_result.ok());
  EXPECT_NE(std::string(small_result.error().message()).find("the buffer has 64"),
            std::string::npos)
      << small_result.error().message();
  // Too many list entries.
  std::vector<HeadOutput> heads(kMaxListLength + 1);
  f.embedding = {};
  f.heads = heads;
  EXPECT_EQ(encode_payload(f, scratch).error().code(), ErrorCode::kInvalidArgument);
  // A misaligned buffer.
  EXPECT_EQ(encode_payload(sample_ack(), std::span(scratch).subspan(1, 256)).error().code(),
            ErrorCode::kInvalidArgument);
}

TEST(Messages, BoundCoversRandomMessages) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  alignas(8) static std::byte scratch[kEncodeBufferSize];
  for (int iter = 0; iter < 300; ++iter) {
    std::vector<std::vector<float>> probs(static_cast<size_t>(rng.int_in(0, 20)));
    std::vector<HeadOutput> heads;
    for (auto& p : probs) {
      p = rng.floats(static_cast<size_t>(rng.int_in(0, 40)), 0, 1);
      heads.push_back(HeadOutput{static_cast<uint16_t>(heads.size()), p});
    }
    const std::vector<float> emb = rng.floats(static_cast<size_t>(rng.int_in(0, 1024)), -1, 1);
    FramePrediction f = sample_frame_prediction(false);
    f.heads = heads;
    f.embedding = emb;
    Result<std::span<const std::byte>> r = encode_payload(f, scratch);
    ASSERT_TRUE(r.ok()) << r.error().message();
    Result<FramePredictionView> v = decode_frame_prediction(r.value());
    ASSERT_TRUE(v.ok());
    ASSERT_EQ(v.value().head_count(), heads.size());
    ASSERT_EQ(v.value().embedding().size(), emb.size());
  }
}

TEST(Messages, FrameImageRoundTrip) {
  const FrameImage in = sample_frame_image();
  const Encoded e = encode(in);
  Result<FrameImage> r = decode_frame_image(e.bytes());
  ASSERT_TRUE(r.ok());
  const FrameImage& f = r.value();
  EXPECT_EQ(f.sensor, in.sensor);
  EXPECT_EQ(f.frame_sequence, in.frame_sequence);
  EXPECT_EQ(f.capture_ns, in.capture_ns);
  EXPECT_EQ(f.kind, in.kind);
  EXPECT_EQ(f.width, in.width);
  EXPECT_EQ(f.height, in.height);
  EXPECT_EQ(f.format, in.format);
  EXPECT_EQ(f.contact, in.contact);
  EXPECT_EQ(f.mask_width, in.mask_width);
  EXPECT_EQ(f.mask_height, in.mask_height);
  EXPECT_TRUE(std::equal(f.mask.begin(), f.mask.end(), in.mask.begin(), in.mask.end()));
  EXPECT_TRUE(std::equal(f.data.begin(), f.data.end(), in.data.begin(), in.data.end()));
  EXPECT_TRUE(mask_cell(f.mask, 32, 4, 0));  // byte 0 = 0xF0: cells 4-7 of row 0
  EXPECT_FALSE(mask_cell(f.mask, 32, 3, 0));
  EXPECT_TRUE(verify_payload(MessageType::kFrameImage, e.bytes()).ok());
}

// frame_image_overhead() is what a board relies on to size its JPEG buffer: an image of exactly
// kMaxPayloadSize - overhead fits, for every mask a contact gate can make (up to 256x256 cells
// would not fit a ubyte: the grid is at most 255 per side on the wire).
TEST(Messages, FrameImageOfTheAdvertisedLargestSizeFits) {
  alignas(8) static std::byte scratch[kEncodeBufferSize];
  static std::vector<uint8_t> data(kMaxPayloadSize), mask(255 * 255 / 8 + 1);
  for (const auto& [w, h] :
       {std::pair{0, 0}, std::pair{32, 24}, std::pair{1, 1}, std::pair{255, 255}}) {
    FrameImage f = sample_frame_image();
    f.mask_width = static_cast<uint8_t>(w);
    f.mask_height = static_cast<uint8_t>(h);
    f.mask = std::span<const uint8_t>(mask).first((static_cast<size_t>(w * h) + 7) / 8);
    f.data =
        std::span<const uint8_t>(data).first(kMaxPayloadSize - frame_image_overhead(f.mask.size()));
    Result<std::span<const std::byte>> r = encode_payload(f, scratch);
    ASSERT_TRUE(r.ok()) << w << "x" << h << ": " << r.error().message();
    f.data = std::span<const uint8_t>(data).first(kMaxPayloadSize - f.mask.size());  // too large
    EXPECT_EQ(encode_payload(f, scratch).error().code(), ErrorCode::kProtocolTooLarge);
  }
  FrameImage bad = sample_frame_image();
  bad.mask_width = 31;  // 31x24 cells need 93 bytes, the sample has 96
  EXPECT_EQ(encode_payload(bad, scratch).error().code(), ErrorCode::kInvalidArgument);
}

TEST(Names, EveryEnumHasAName) {
  for (MessageType t :
       {MessageType::kHello, MessageType::kFramePrediction, MessageType::kGraspPrediction,
        MessageType::kStats, MessageType::kError, MessageType::kAck, MessageType::kNack,
        MessageType::kPong, MessageType::kFrameImage, MessageType::kCommand}) {
    EXPECT_NE(message_type_name(t), nullptr);
  }
  EXPECT_EQ(message_type_name(static_cast<MessageType>(0x42)), nullptr);
  for (int k = 0; k <= 9; ++k) {
    const char* name = command_kind_name(static_cast<CommandKind>(k));
    ASSERT_NE(name, nullptr);
    CommandKind back;
    if (k > 0) {
      ASSERT_TRUE(command_kind_from_name(name, back));
      EXPECT_EQ(static_cast<int>(back), k);
    }
  }
  EXPECT_STREQ(image_kind_name(ImageKind::kView), "view");
  EXPECT_STREQ(image_kind_name(ImageKind::kInput), "input");
  EXPECT_STREQ(image_format_name(ImageFormat::kJpeg), "jpeg");
  EXPECT_STREQ(drop_cause_name(DropCause::kImageBusy), "image_busy");
  for (int c = 0; c <= 6; ++c) EXPECT_NE(drop_cause_name(static_cast<DropCause>(c)), nullptr);
  EXPECT_EQ(drop_cause_name(static_cast<DropCause>(99)), nullptr);
}

}  // namespace
}  // namespace tlvlink::protocol
