// A board program on the minimal runtime that streams (tests/minimal): a replayed camera
// recording (runtime/capture) through the decoder, the pipeline and runtime/stream into stream
// bytes in memory, which are then decoded with runtime/protocol and checked.
//   tlvlink_board_stream --write-recording PATH   the fixture: a YUYV camera's 30 frames (idle,
//                                                 pressed, idle), made at test time
//   tlvlink_board_stream MODEL.tlvm PATH          exit 0: the bytes decode to the Hello, one
//                                                 FramePrediction per frame in order (heads only
//                                                 where the encoder ran) and the Stats, with no
//                                                 allocation between the first frame and the Stats
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "support/alloc_counter.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/replay_source.h"
#include "tlvlink/clock.h"
#include "tlvlink/image/convert.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/pipeline/frame_processor.h"
#include "tlvlink/protocol/protocol.h"
#include "tlvlink/stream/stream.h"
#include "tlvlink/tlvlink.h"

namespace {

using namespace tlvlink;

constexpr int32_t kW = 320, kH = 240;
constexpr int kIdle = 10, kPressed = 12, kIdleAfter = 8;
constexpr int kFrames = kIdle + kPressed + kIdleAfter;
constexpr int64_t kFrameNs = 40 * kNsPerMs;  // 25 fps

int fail(const char* what, const Error& e) {
  std::printf("%s: %s\n", what, e.message());
  return 1;
}

// The gel at rest or pressed in its middle, as the camera's YUYV bytes.
std::vector<uint8_t> camera_frame(bool pressed, const image::FrameFormat& format) {
  std::vector<uint8_t> rgb(static_cast<size_t>(kW * kH * 3));
  for (int32_t y = 0; y < kH; ++y)
    for (int32_t x = 0; x < kW; ++x) {
      const double dx = (x - kW / 2.0) / 30, dy = (y - kH / 2.0) / 30;
      const double press = pressed ? 50 * std::exp(-(dx * dx + dy * dy)) : 0;
      uint8_t* p = &rgb[static_cast<size_t>((y * kW + x) * 3)];
      p[0] = static_cast<uint8_t>(90 + x / 8 + press * dx);
      p[1] = static_cast<uint8_t>(110 + y / 8 + press);
      p[2] = static_cast<uint8_t>(130 - press * dy);
    }
  std::vector<uint8_t> out(image::frame_bytes(format));
  (void)image::upright_rgb_to_camera(rgb, format, image::Orientation::kUpright, out);
  return out;
}

int write_recording(const std::string& path) {
  capture::RecordingFormat format;
  format.format = {image::PixelFormat::kYuyv, kW, kH, kW * 2};
  format.fps_numerator = 25;
  capture::WriterOptions options;
  options.origin_ns = 0;
  options.overwrite = true;
  auto w = capture::RecordingWriter::create(path, format, options);
  if (!w.ok()) return fail("recording", w.error());
  const std::vector<uint8_t> idle = camera_frame(false, format.format);
  const std::vector<uint8_t> pressed = camera_frame(true, format.format);
  capture::RecordedBytes idle_bytes{}, pressed_bytes{};
  for (int i = 0; i < kFrames; ++i) {
    const bool press = i >= kIdle && i < kIdle + kPressed;
    const int64_t t = i * kFrameNs;
    const uint32_t seq = static_cast<uint32_t>(i);
    Status st;
    if (i == 0 || i == kIdle) {  // each image's bytes once, then repeats
      auto b = w->append(press ? pressed : idle, t, seq);
      if (!b.ok()) return fail("append", b.error());
      (press ? pressed_bytes : idle_bytes) = *b;
    } else {
      st = w->append_repeat(press ? pressed_bytes : idle_bytes, t, seq);
    }
    if (!st.ok()) return fail("append", st.error());
  }
  const Status closed = w->close();
  if (!closed.ok()) return fail("close", closed.error());
  std::printf("wrote %s: %d frames\n", path.c_str(), kFrames);
  return 0;
}

// The link: stream bytes appended to memory (capacity reserved at start).
struct MemoryLink {
  std::vector<std::byte> bytes;
  uint32_t sequence = 0;
  alignas(8) std::byte scratch[protocol::kEncodeBufferSize];
  std::byte wire[protocol::kMaxWireFrameSize];
  template <typename M>
  bool send(const M& m) {
    protocol::FrameHeader h;
    h.sequence = sequence++;
    h.send_ns = board_clock_ns();
    auto n = protocol::encode_message(m, h, scratch, wire);
    if (!n.ok() || bytes.size() + *n > bytes.capacity()) return false;
    bytes.insert(bytes.end(), wire, wire + *n);
    return true;
  }
};

struct Expected {
  std::vector<uint32_t> sequences;
  std::vector<bool> encoded;
  std::vector<int32_t> head_counts;  // the heads the pipeline reported on each frame
  // Heads in the Hello; heads an encoded frame carries: the per-frame heads always, the press
  // heads from a contact's fourth frame on.
  size_t heads = 0, per_frame = 0, reported = 0;
};

// Decodes the stream and checks it against what was sent. Returns the number of problems.
int check(const std::vector<std::byte>& bytes, const Expected& want) {
  int problems = 0;
  auto expect = [&problems](bool ok, const char* what) {
    if (!ok) std::printf("FAIL: %s\n", what), ++problems;
  };
  protocol::Deframer deframer;
  size_t frames = 0, hellos = 0, stats = 0, with_heads = 0;
  uint32_t next_sequence = 0;
  deframer.feed(bytes, [&](const protocol::ReceivedFrame& f) {
    expect(f.verdict == protocol::FrameVerdict::kOk, "a frame was rejected");
    if (f.verdict != protocol::FrameVerdict::kOk) return;
    expect(f.header.sequence == next_sequence++, "frame header sequence in order");
    switch (f.header.type) {
      case protocol::MessageType::kHello: {
        auto h = protocol::decode_hello(f.payload);
        expect(h.ok() && h->sensor_count() == 1 && h->sensor(0).name == "gel",
               "Hello names the sensor");
        expect(h.ok() && h->head_count() == want.heads, "Hello lists the model's heads");
        expect(h.ok() && h->stage_name_count() == stream::kStageNames.size(), "Hello's stages");
        ++hellos;
        break;
      }
      case protocol::MessageType::kFramePrediction: {
        auto p = protocol::decode_frame_prediction(f.payload);
        expect(p.ok(), "FramePrediction decodes");
        if (!p.ok() || frames >= want.sequences.size()) break;
        expect(p->frame_sequence() == want.sequences[frames], "frame sequence as replayed");
        const bool encoded = want.encoded[frames];
        const auto n = static_cast<size_t>(want.head_counts[frames]);
        expect(
            p->head_count() == n && (encoded ? n >= want.per_frame && n <= want.reported : n == 0),
            "heads exactly where encoded");
        for (size_t k = 0; k < p->head_count(); ++k) {
          double sum = 0;
          for (float v : p->head(k).probabilities)
            sum += std::isfinite(v) ? static_cast<double>(v) : 1e9;
          expect(std::fabs(sum - 1) < 1e-3, "head probabilities sum to 1");
        }
        with_heads += p->head_count() > 0 ? 1 : 0;
        ++frames;
        break;
      }
      case protocol::MessageType::kStats: {
        auto s = protocol::decode_stats(f.payload);
        expect(s.ok() && s->sensor_count() == 1 && s->sensor(0).frames == want.sequences.size(),
               "Stats count the frames");
        ++stats;
        break;
      }
      default: expect(false, "an unexpected message type");
    }
  });
  expect(deframer.counters().rejected() == 0, "no rejected bytes");
  expect(hellos == 1 && stats == 1, "one Hello, one Stats");
  expect(frames == want.sequences.size(), "one FramePrediction per frame");
  expect(with_heads > 0 && with_heads < frames, "some frames encoded, some gated");
  std::printf("stream: %zu bytes, %zu frame predictions (%zu with heads), %d problem(s)\n",
              bytes.size(), frames, with_heads, problems);
  return problems;
}

int run(const char* model_path, const std::string& recording) {
  auto model = Model::load_file(model_path);
  if (!model.ok()) return fail(model_path, model.error());
  const Model& m = **model;
#if defined(TLVLINK_HAVE_XNNPACK)
  auto exec = make_executor(m, ExecutorKind::kXnnpack, {.threads = 1});
#else
  auto exec = make_executor(m, ExecutorKind::kReference, {});
#endif
  if (!exec.ok()) return fail("executor", exec.error());
  const pipeline::SensorSetup sensors[] = {{"gel", kW, kH, 3, -1, ""}};
  pipeline::ProcessorOptions options;
  options.contact.reference_frames = 5;
  auto processor = pipeline::FrameProcessor::create(m, **exec, sensors, options);
  if (!processor.ok()) return fail("pipeline", processor.error());
  capture::ReplayConfig replay;
  replay.path = recording;
  replay.realtime = false;  // as fast as the pipeline takes them
  auto source = capture::make_replay_source(replay);
  if (!source.ok()) return fail("replay", source.error());
  const Status started = (*source)->start();
  if (!started.ok()) return fail("replay", started.error());
  auto decoder = image::FrameDecoder::create((*source)->format(), {kW, kH, 0.0});
  if (!decoder.ok()) return fail("decoder", decoder.error());

  // The Hello, from the model, the sensor and the heads the pipeline reports.
  const stream::OutputNames names = stream::output_names({"gel"}, (*processor)->heads());
  const stream::SensorDescription described[] = {
      {"gel", "digit", image::pixel_format_name((*source)->format().format), kW, kH, 25}};
  const stream::HelloBuilder hello({"board", "minimal", "0", 1}, m, model_path, described, names);
  stream::MessageMapper mapper(false);
  MemoryLink link;
  link.bytes.reserve(1 << 20);
  if (!link.send(hello.hello())) return std::printf("Hello not sent\n"), 1;

  Expected want;
  want.heads = names.heads.size() + (names.grasp_head.empty() ? 0 : 1);
  want.reported = (*processor)->reported_heads().size();
  for (int16_t k : (*processor)->reported_heads())
    want.per_frame += static_cast<size_t>(k) < (*processor)->heads().per_frame_count() ? 1 : 0;
  want.sequences.reserve(kFrames);
  want.encoded.reserve(kFrames);
  want.head_counts.reserve(kFrames);
  std::vector<uint8_t> view(decoder->output_bytes());
  pipeline::FramePrediction prediction;
  testing::start_counting_allocations();
  for (;;) {
    auto frame = (*source)->next(1000);
    if (!frame.ok()) {
      if (frame.error().code() == ErrorCode::kCaptureEndOfStream) break;
      testing::stop_counting_allocations();
      return fail("replay", frame.error());
    }
    pipeline::FrameTimes times;
    times.capture_ns = frame->timestamp_ns;
    times.dequeued_ns = board_clock_ns();
    const Status decoded = decoder->decode(frame->bytes, view, "gel");
    times.decoded_ns = board_clock_ns();
    const Status processed =
        decoded.ok()
            ? (*processor)
                  ->process(0, frame->sequence, {view.data(), kW, kH, 3, 0}, times, prediction)
            : decoded;
    (*source)->release();
    if (!processed.ok()) {
      testing::stop_counting_allocations();
      return fail("frame", processed.error());
    }
    want.sequences.push_back(static_cast<uint32_t>(frame->sequence));
    want.encoded.push_back(prediction.encoder_ran);
    want.head_counts.push_back(prediction.encoder_ran ? prediction.head_count : 0);
    if (!link.send(mapper.frame(prediction))) return std::printf("frame not sent\n"), 1;
  }
  stream::StreamTotals totals;
  totals.sensors = 1;
  totals.sensor_frames[0] = (*processor)->counters().sensor_frames[0];
  totals.sensor_encoded[0] = (*processor)->counters().sensor_encoder_runs[0];
  totals.sensor_gated[0] = (*processor)->counters().sensor_gated[0];
  const bool stats_sent = link.send(mapper.stats(totals));
  const size_t allocations = testing::stop_counting_allocations();
  if (!stats_sent) return std::printf("Stats not sent\n"), 1;
  std::printf("%zu frames replayed, %zu allocations from the first frame to the Stats\n",
              want.sequences.size(), allocations);
  int problems = check(link.bytes, want);
  if (want.sequences.size() != static_cast<size_t>(kFrames))
    std::printf("FAIL: %zu of %d frames replayed\n", want.sequences.size(), kFrames), ++problems;
  if (allocations != 0) std::printf("FAIL: the frame loop allocated\n"), ++problems;
  return problems;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--write-recording") return write_recording(argv[2]);
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s --write-recording PATH | %s MODEL.tlvm RECORDING\n", argv[0],
                 argv[0]);
    return 2;
  }
  const int problems = run(argv[1], argv[2]);
  std::printf("board stream: %s\n", problems == 0 ? "PASS" : "FAIL");
  return problems == 0 ? 0 : 1;
}
