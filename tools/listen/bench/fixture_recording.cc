#include "fixture_recording.h"

#include <flatbuffers/flatbuffers.h>
#include <sys/stat.h>
#include <unistd.h>

#include <vector>

#include "stream_fixture.h"
#include "stream_generated.h"
#include "tlvlink/listen/recording.h"
#include "tlvlink/protocol/encode.h"

namespace tlvlink::listen {
namespace {

using protocol::MessageType;

constexpr int64_t kOffset = 5'000'000'000;  // board clock - host clock
constexpr int64_t kStart = 1'000'000'000;   // host clock at the first record

class Builder {
 public:
  explicit Builder(std::unique_ptr<RecordingWriter> w) : w_(std::move(w)) {}

  // A board frame sent at host time `host_ns` (its header carries board time).
  template <typename M>
  std::vector<std::byte> frame(const M& m, uint32_t seq, int64_t host_ns, uint16_t flags = 0,
                               uint8_t major = 1) {
    protocol::FrameHeader h;
    h.version_major = major;
    h.sequence = seq;
    h.flags = flags;
    h.send_ns = host_ns + kOffset;
    Result<size_t> n = protocol::encode_message(m, h, scratch_, wire_);
    return std::vector<std::byte>(wire_, wire_ + n.value());
  }
  std::vector<std::byte> raw_frame(MessageType type, std::span<const std::byte> payload,
                                   uint32_t seq, int64_t host_ns) {
    protocol::FrameHeader h;
    h.type = type;
    h.sequence = seq;
    h.send_ns = host_ns + kOffset;
    Result<size_t> n = protocol::encode_frame(h, payload, wire_);
    return std::vector<std::byte>(wire_, wire_ + n.value());
  }
  Status put(RecordKind kind, int64_t t, std::span<const std::byte> bytes) {
    return w_->write(kind, t, bytes);
  }
  Status text(RecordKind kind, int64_t t, std::string_view s) {
    return w_->write(kind, t, std::as_bytes(std::span(s.data(), s.size())));
  }
  RecordingWriter& writer() { return *w_; }

 private:
  std::unique_ptr<RecordingWriter> w_;
  alignas(8) std::byte scratch_[protocol::kEncodeBufferSize];
  std::byte wire_[protocol::kMaxWireFrameSize];
};

std::vector<std::byte> cat(std::initializer_list<std::vector<std::byte>> parts) {
  std::vector<std::byte> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// A FramePrediction as a newer minor version writes it: two fields this schema does not have.
std::vector<std::byte> future_prediction_payload() {
  flatbuffers::FlatBufferBuilder fbb;
  const auto note = fbb.CreateString("field from protocol 1.3");
  const tlvlink::wire::FrameTiming timing(kStart + kOffset + 900, kStart + kOffset + 950,
                                          kStart + kOffset + 990);
  const auto start = fbb.StartTable();
  fbb.AddElement<uint8_t>(tlvlink::wire::FramePrediction::VT_SENSOR, 1, 0);
  fbb.AddElement<uint32_t>(tlvlink::wire::FramePrediction::VT_FRAME_SEQUENCE, 77, 0);
  fbb.AddStruct(tlvlink::wire::FramePrediction::VT_TIMING, &timing);
  fbb.AddElement<uint8_t>(tlvlink::wire::FramePrediction::VT_CONTACT, 1, 0);
  fbb.AddElement<uint64_t>(4 + 2 * 7, 123456789, 0);
  fbb.AddOffset(4 + 2 * 8, note);
  fbb.Finish(flatbuffers::Offset<tlvlink::wire::FramePrediction>(fbb.EndTable(start)));
  const auto* p = reinterpret_cast<const std::byte*>(fbb.GetBufferPointer());
  return std::vector<std::byte>(p, p + fbb.GetSize());
}

}  // namespace

Status write_fixture_recording(const std::string& path, bool cut_last_record) {
  TLV_ASSIGN_OR_RETURN(auto writer, RecordingWriter::create(path));
  Builder b(std::move(writer));
  using namespace protocol;
  int64_t t = kStart;
  uint32_t seq = 0;
  TLV_TRY(b.text(RecordKind::kLinkUp, t, "serial:/dev/ttyACM0 (fixture)"));
  // The client's own Info (seq 0) and TimeSync (seq 1).
  Command info, sync, ping;
  info.kind = CommandKind::kInfo;
  sync.kind = CommandKind::kTimeSync;
  ping.kind = CommandKind::kPing;
  const int64_t t1 = t + 100'000;
  {
    FrameHeader h;
    alignas(8) static std::byte scratch[kEncodeBufferSize];
    std::byte wire[kMaxWireFrameSize];
    std::vector<std::byte> sent;
    for (auto [c, s] : {std::pair{info, 0u}, std::pair{sync, 1u}}) {
      h.sequence = s;
      h.send_ns = t1;
      Result<size_t> n = encode_message(c, h, scratch, wire);
      sent.insert(sent.end(), wire, wire + n.value());
    }
    TLV_TRY(b.put(RecordKind::kSentAuto, t1, sent));
  }
  // Hello (after a lone delimiter), the Info's Ack (consumed), the TimeSync's Pong (consumed):
  // t2 = t1 + 50 us (board), t3 = t2 + 10 us, t4 = t3 + 50 us (host).
  const int64_t t2 = t1 + 50'000 + kOffset, t3_host = t1 + 60'000, t4 = t1 + 110'000;
  std::vector<std::byte> hello_chunk = {std::byte{0}};
  const auto hello = b.frame(testing::fixture_hello(), seq++, t1 - 50'000);
  hello_chunk.insert(hello_chunk.end(), hello.begin(), hello.end());
  TLV_TRY(b.put(RecordKind::kReceived, t1 - 40'000, hello_chunk));
  TLV_TRY(b.put(RecordKind::kReceived, t4 - 1000,
                b.frame(Ack{0, CommandKind::kInfo}, seq++, t3_host - 5000)));
  TLV_TRY(b.put(RecordKind::kReceived, t4, b.frame(Pong{1, t1, t2}, seq++, t3_host)));
  t = t4;
  // Two predictions, the second cut across two reads; one with an embedding.
  testing::PredictionStorage st0, st1;
  const auto f0 = b.frame(testing::fixture_prediction(0, st0, true, t + kOffset - 3'000'000), seq++,
                          t + 500'000);
  const auto f1 = b.frame(testing::fixture_prediction(1, st1, false, t + kOffset - 2'000'000),
                          seq++, t + 600'000);
  std::vector<std::byte> both = cat({f0, f1});
  const size_t cut = f0.size() + f1.size() / 2;
  TLV_TRY(b.put(RecordKind::kReceived, t + 700'000, std::span(both).first(cut)));
  TLV_TRY(b.put(RecordKind::kReceived, t + 800'000, std::span(both).subspan(cut)));
  t += 1'000'000;
  // Grasps, computed and not.
  const std::array<GraspFrame, 2> frames = {
      GraspFrame{0, GraspPhase::kBefore, 0, t + kOffset - 5'000'000},
      GraspFrame{1, GraspPhase::kDuring, 1, t + kOffset - 4'000'000}};
  GraspPrediction computed;
  computed.grasp_id = 1;
  computed.status = GraspStatus::kComputed;
  computed.probability = 0.8125f;
  computed.frames = frames;
  computed.phase_source = PhaseSource::kCommand;
  computed.closed_ns = t + kOffset - 6'000'000;
  computed.lifting_ns = t + kOffset - 4'500'000;
  computed.infer_end_ns = t + kOffset - 100'000;
  GraspPrediction missing;
  missing.grasp_id = 2;
  missing.status = GraspStatus::kNotComputed;
  missing.reason = GraspReason::kMissingFinger;
  missing.reason_text = "sensor 1 sent no frame during the grasp";
  missing.phase_source = PhaseSource::kDetected;
  TLV_TRY(b.put(RecordKind::kReceived, t,
                cat({b.frame(computed, seq++, t - 20'000), b.frame(missing, seq++, t - 10'000)})));
  t += 1'000'000;
  // Stats and an error report.
  const std::array<SensorStats, 2> sensors = {SensorStats{0, 59.5f, 600, 400, 200},
                                              SensorStats{1, 60.0f, 601, 401, 200}};
  const std::array<DropCount, 3> drops = {DropCount{DropCause::kCaptureGap, 2, 0},
                                          DropCount{DropCause::kQueueFull, 0, kNoSensor},
                                          DropCount{static_cast<DropCause>(42), 7, kNoSensor}};
  Stats stats;
  stats.uptime_ns = 10'000'000'000;
  stats.sensors = sensors;
  stats.drops = drops;
  stats.cpu_percent = 37.5f;
  stats.cpu_cores = 2;
  stats.rss_bytes = 33'554'432;
  stats.link = LinkStats{true, 0, 12, 3456, 2, 0, 0, 0, 262'144};
  TLV_TRY(b.put(RecordKind::kReceived, t, b.frame(stats, seq++, t - 10'000)));
  TLV_TRY(
      b.put(RecordKind::kReceived, t + 1000,
            b.frame(ErrorReport{400, "capture", "/dev/video2: no frame for 500 ms; reopening", 1},
                    seq++, t - 5000)));
  t += 1'000'000;
  // The user's ping (seq 2) and a refused setting (seq 3): their replies are delivered.
  {
    FrameHeader h;
    alignas(8) static std::byte scratch[kEncodeBufferSize];
    std::byte wire[kMaxWireFrameSize];
    h.sequence = 2;
    h.send_ns = t;
    Result<size_t> n = encode_message(ping, h, scratch, wire);
    TLV_TRY(b.put(RecordKind::kSent, t, std::span<const std::byte>(wire, n.value())));
  }
  TLV_TRY(b.put(RecordKind::kReceived, t + 200'000,
                cat({b.frame(Pong{2, t, t + 80'000 + kOffset}, seq++, t + 90'000),
                     b.frame(Nack{3, CommandKind::kSetConfig, 300, "unknown key 'treads'"}, seq++,
                             t + 95'000)})));
  t += 1'000'000;
  // Skipped or refused: an unknown message type, garbage, a corrupted frame, a major-2 frame.
  const std::byte blob[8] = {std::byte{1}, std::byte{2}, std::byte{3}, std::byte{4}};
  auto corrupted = b.frame(ErrorReport{1, "x", "y", 0}, seq++, t);
  corrupted[corrupted.size() / 2] ^= std::byte{0x20};
  const std::byte garbage[] = {std::byte{0x13}, std::byte{0x37}, std::byte{0xFF}, std::byte{0x00}};
  TLV_TRY(b.put(RecordKind::kReceived, t,
                cat({b.raw_frame(static_cast<MessageType>(0x42), blob, seq++, t),
                     std::vector<std::byte>(garbage, garbage + 4), corrupted,
                     b.frame(Ack{9, CommandKind::kStart}, 500, t, 0, 2)})));
  // A prediction from a newer minor version, after a gap of 3 frames, and one flagged delayed.
  seq += 3;
  TLV_TRY(b.put(
      RecordKind::kReceived, t + 100'000,
      b.raw_frame(MessageType::kFramePrediction, future_prediction_payload(), seq++, t + 50'000)));
  testing::PredictionStorage st2;
  TLV_TRY(b.put(RecordKind::kReceived, t + 200'000,
                b.frame(testing::fixture_prediction(2, st2, false, t + kOffset - 9'000'000), seq++,
                        t + 150'000, kFlagDelayed)));
  t += 1'000'000;
  // The link drops, comes back, and the board has restarted (new boot id, sequence from 0).
  TLV_TRY(b.text(RecordKind::kLinkDown, t, "serial:/dev/ttyACM0: hangup"));
  t += 500'000'000;
  TLV_TRY(b.text(RecordKind::kLinkUp, t, "serial:/dev/ttyACM0 (fixture)"));
  Hello restarted = testing::fixture_hello();
  restarted.boot_id = 0xB007;
  seq = 0;
  TLV_TRY(b.put(RecordKind::kReceived, t + 100'000, b.frame(restarted, seq++, t + 50'000)));
  testing::PredictionStorage st3;
  TLV_TRY(b.put(RecordKind::kReceived, t + 300'000,
                b.frame(testing::fixture_prediction(3, st3, false, t + kOffset + 100'000), seq++,
                        t + 250'000)));
  if (!cut_last_record) return b.writer().flush();
  // A last record cut short, as when the recorder is killed while writing it.
  TLV_TRY(b.put(RecordKind::kReceived, t + 400'000, std::span<const std::byte>(blob, 4)));
  TLV_TRY(b.writer().flush());
  struct stat st;
  TLV_ENSURE(::stat(path.c_str(), &st) == 0 && ::truncate(path.c_str(), st.st_size - 2) == 0,
             ErrorCode::kIo, "cutting %s", path.c_str());
  return Status();
}

Status write_non_utf8_recording(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(auto writer, RecordingWriter::create(path));
  Builder b(std::move(writer));
  const int64_t t = kStart;
  TLV_TRY(b.text(RecordKind::kLinkUp, t, "serial:/dev/ttyACM0 (fixture)"));
  TLV_TRY(b.put(RecordKind::kReceived, t + 1000, b.frame(testing::fixture_hello(), 0, t + 1000)));
  protocol::ErrorReport bad;
  bad.code = 0;
  bad.name = "info";
  bad.text = "bad \xff\xfe bytes";
  TLV_TRY(b.put(RecordKind::kReceived, t + 2000, b.frame(bad, 1, t + 2000)));
  protocol::ErrorReport after = bad;
  after.text = "after";
  TLV_TRY(b.put(RecordKind::kReceived, t + 3000, b.frame(after, 2, t + 3000)));
  return Status();
}

}  // namespace tlvlink::listen
