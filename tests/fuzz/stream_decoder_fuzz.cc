// libFuzzer target for the stream protocol's receiving side (runtime/protocol): untrusted bytes
// from a serial or USB link. The first input byte picks the mode:
//   even: the bytes are a link's byte stream, fed to a Deframer in pieces whose sizes come from
//         the input; every good frame's payload is verified for its type and read in full;
//   odd:  the rest is one payload, given to every message decoder (CRC-32 keeps random bytes from
//         ever reaching the decoders through the framing, so they are fuzzed directly too).
// A payload that verifies must be safe to read completely: the walk touches every field.
// Run by tools/setup/run_tests.sh fuzz (seeds from make_stream_fuzz_corpus).

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/views.h"

// Every read lands here: a global the compiler must assume someone else reads.
uint64_t g_stream_fuzz_sink = 0;

namespace {

using namespace tlvlink::protocol;

uint64_t& g_sink = g_stream_fuzz_sink;

void touch(std::string_view s) {
  g_sink += s.size() + (s.empty() ? 0 : static_cast<uint8_t>(s.back()));
}
template <typename T>
void touch(std::span<const T> v) {
  g_sink += v.size();
  for (const T& x : v) g_sink += static_cast<uint64_t>(x != x ? 1 : x > 0);
}

void walk(MessageType type, std::span<const std::byte> payload) {
  switch (type) {
    case MessageType::kHello:
      if (auto r = decode_hello(payload); r.ok()) {
        const HelloView& h = r.value();
        touch(h.device()), touch(h.board()), touch(h.firmware_version()), touch(h.model_id()),
            touch(h.clock());
        g_sink += h.boot_id() + h.schema_hash() + h.model_checksum() + h.embedding_dim() +
                  h.max_frame_size();
        for (size_t i = 0; i < h.sensor_count(); ++i) {
          const SensorInfo s = h.sensor(i);
          touch(s.name), touch(s.model), touch(s.serial), touch(s.pixel_format);
        }
        for (size_t i = 0; i < h.head_count(); ++i) {
          const HeadInfoView v = h.head(i);
          touch(v.name());
          for (size_t k = 0; k < v.label_count(); ++k) touch(v.label(k));
          g_sink += static_cast<uint64_t>(v.kind()) + (v.accuracy() > 0) + (v.majority_rate() > 0);
        }
        for (size_t i = 0; i < h.stage_name_count(); ++i) touch(h.stage_name(i));
      }
      break;
    case MessageType::kFramePrediction:
      if (auto r = decode_frame_prediction(payload); r.ok()) {
        const FramePredictionView& f = r.value();
        g_sink += f.sensor() + f.frame_sequence() + static_cast<uint64_t>(f.timing().capture_ns) +
                  f.contact();
        touch(f.stage_ns());
        for (size_t i = 0; i < f.head_count(); ++i) touch(f.head(i).probabilities);
        touch(f.embedding());
      }
      break;
    case MessageType::kGraspPrediction:
      if (auto r = decode_grasp_prediction(payload); r.ok()) {
        const GraspPredictionView& g = r.value();
        touch(g.reason_text());
        for (size_t i = 0; i < g.frame_count(); ++i) g_sink += g.frame(i).frame_sequence;
        g_sink += g.grasp_id() + (g.probability() > 0) + static_cast<uint64_t>(g.closed_ns());
      }
      break;
    case MessageType::kStats:
      if (auto r = decode_stats(payload); r.ok()) {
        const StatsView& s = r.value();
        for (size_t i = 0; i < s.sensor_count(); ++i) g_sink += s.sensor(i).frames;
        for (size_t i = 0; i < s.drop_count(); ++i) g_sink += s.drop(i).count;
        g_sink += s.link().frames_sent + s.rss_bytes();
      }
      break;
    case MessageType::kError:
      if (auto r = decode_error_report(payload); r.ok())
        touch(r.value().name), touch(r.value().text);
      break;
    case MessageType::kAck:
      if (auto r = decode_ack(payload); r.ok()) g_sink += r.value().command_sequence;
      break;
    case MessageType::kNack:
      if (auto r = decode_nack(payload); r.ok()) touch(r.value().text);
      break;
    case MessageType::kPong:
      if (auto r = decode_pong(payload); r.ok())
        g_sink += static_cast<uint64_t>(r.value().host_send_ns);
      break;
    case MessageType::kFrameImage:
      if (auto r = decode_frame_image(payload); r.ok())
        g_sink += r.value().data.size() + r.value().mask.size();
      break;
    case MessageType::kCommand:
      if (auto r = decode_command(payload); r.ok()) touch(r.value().key), touch(r.value().value);
      break;
  }
}

constexpr MessageType kTypes[] = {MessageType::kHello,
                                  MessageType::kFramePrediction,
                                  MessageType::kGraspPrediction,
                                  MessageType::kStats,
                                  MessageType::kError,
                                  MessageType::kAck,
                                  MessageType::kNack,
                                  MessageType::kPong,
                                  MessageType::kFrameImage,
                                  MessageType::kCommand};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const auto* bytes = reinterpret_cast<const std::byte*>(data);
  if ((data[0] & 1) == 0) {
    static Deframer deframer;  // 33 KB: built once, like a receiver
    deframer.reset();
    // Piece sizes from the input's second byte: 1 (byte by byte) ... 256.
    const size_t piece = size > 1 ? static_cast<size_t>(data[1]) + 1 : 1;
    for (size_t at = 1; at < size; at += piece) {
      deframer.feed(std::span<const std::byte>(bytes + at, std::min(piece, size - at)),
                    [](const ReceivedFrame& f) {
                      if (f.verdict != FrameVerdict::kOk) return;
                      if (verify_payload(f.header.type, f.payload).ok())
                        walk(f.header.type, f.payload);
                    });
    }
    return 0;
  }
  // Payload mode: an aligned copy (receivers hand decoders 8-byte aligned payloads).
  static std::vector<uint64_t> aligned;
  aligned.assign((size - 1 + 7) / 8, 0);
  std::memcpy(aligned.data(), data + 1, size - 1);
  const std::span<const std::byte> payload(reinterpret_cast<const std::byte*>(aligned.data()),
                                           size - 1);
  for (MessageType t : kTypes) walk(t, payload);
  return 0;
}
