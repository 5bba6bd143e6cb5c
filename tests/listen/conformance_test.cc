// The stream's conformance cases (runtime/protocol/conformance/cases.json, README §16): byte
// sequences and the outcome a receiver must reach for each delimited segment. This test makes
// the cases (so the file stays what this code says: TLVLINK_REGENERATE_CONFORMANCE=1 rewrites
// it after a deliberate change) and runs every case through the C++ receiving side: Deframer,
// payload verification, the host's handling of unknown and command frames, and the JSON line
// for the fields a case names. tools/python/tests/test_conformance.py runs the same file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tlvlink/crc32.h"
#include "tlvlink/listen/format.h"
#include "tlvlink/listen/message.h"
#include "tlvlink/protocol/cobs.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/names.h"

namespace tlvlink::listen {
namespace {

using nlohmann::ordered_json;
using protocol::FrameHeader;
using protocol::MessageType;
using Bytes = std::vector<std::byte>;

constexpr const char* kCasesPath = TLVLINK_SOURCE_DIR "/runtime/protocol/conformance/cases.json";

std::string hex(const Bytes& b) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (std::byte x : b) {
    out += kDigits[static_cast<uint8_t>(x) >> 4];
    out += kDigits[static_cast<uint8_t>(x) & 15];
  }
  return out;
}

Bytes unhex(const std::string& s) {
  Bytes out;
  for (size_t i = 0; i + 1 < s.size(); i += 2)
    out.push_back(static_cast<std::byte>(std::stoi(s.substr(i, 2), nullptr, 16)));
  return out;
}

// A frame's bytes before COBS: header, payload, CRC-32 (the header's payload length as given).
Bytes body(const FrameHeader& h, const Bytes& payload) {
  Bytes out(protocol::kHeaderSize);
  protocol::write_header(h, out.data());
  out.insert(out.end(), payload.begin(), payload.end());
  const uint32_t crc = crc32(out);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::byte>((crc >> (8 * i)) & 0xFF));
  return out;
}

// COBS and the delimiter.
Bytes wire(const Bytes& frame) {
  Bytes out(protocol::cobs_max_encoded_size(frame.size()) + 1);
  protocol::CobsEncoder enc(out);
  enc.put(frame);
  out.resize(enc.finish().value());
  out.push_back(std::byte{0});
  return out;
}

template <typename M>
Bytes payload_of(const M& m) {
  alignas(8) static std::byte scratch[protocol::kEncodeBufferSize];
  const std::span<const std::byte> p = protocol::encode_payload(m, scratch).value();
  return Bytes(p.begin(), p.end());
}

FrameHeader header(MessageType type, uint32_t sequence, size_t payload, uint16_t flags = 0) {
  FrameHeader h;
  h.type = type;
  h.sequence = sequence;
  h.flags = flags;
  h.payload_length = static_cast<uint32_t>(payload);
  h.send_ns = 1'000'000'000 + sequence * 1000;
  return h;
}

template <typename M>
Bytes message(const M& m, uint32_t sequence, uint16_t flags = 0) {
  const Bytes p = payload_of(m);
  return body(header(protocol::MessageTypeOf<M>::value, sequence, p.size(), flags), p);
}

ordered_json one(const std::string& name, const std::string& note, const Bytes& bytes,
                 std::vector<std::string> expect) {
  return {{"name", name}, {"note", note}, {"wire", {{{"hex", hex(bytes)}}}}, {"expect", expect}};
}

// Every case, in order. Deterministic: fixed times, sequences and contents.
ordered_json make_cases() {
  ordered_json cases = ordered_json::array();
  // Valid messages of every board -> host type.
  static const std::string_view kLabels[] = {"soft", "hard"};
  static const std::string_view kStages[] = {"dequeue",    "decode",  "queue",
                                             "preprocess", "encoder", "heads"};
  protocol::SensorInfo sensor{0, "left", "digit", "", "yuyv", 320, 240, 60.0f};
  protocol::HeadInfo head{"hardness", protocol::HeadKind::kLinear, kLabels, 0.9f, 0.5f};
  protocol::Hello hello;
  hello.device = "conformance";
  hello.board = "test";
  hello.firmware_version = "1";
  hello.boot_id = 0x5EED;
  hello.model_id = "model";
  hello.sensors = std::span(&sensor, 1);
  hello.heads = std::span(&head, 1);
  hello.stage_names = kStages;
  cases.push_back(one("hello", "a Hello (its schema_hash is this build's)", wire(message(hello, 0)),
                      {"ok:hello"}));
  static const float kProbs[] = {0.25f, 0.75f};
  static const uint32_t kStageNs[] = {100, 200, 300, 400, 500, 600};
  protocol::HeadOutput out{0, kProbs};
  protocol::FramePrediction encoded;
  encoded.frame_sequence = 41;
  encoded.timing = {2'000'000'000, 2'000'100'000, 2'000'900'000};
  encoded.stage_ns = kStageNs;
  encoded.contact = true;
  encoded.heads = std::span(&out, 1);
  cases.push_back(one("frame_prediction_encoded",
                      "a frame the encoder ran on: heads, infer_end_ns set",
                      wire(message(encoded, 1)), {"ok:frame_prediction"}));
  protocol::FramePrediction gated;
  gated.frame_sequence = 42;
  gated.timing = {2'016'000'000, 2'016'100'000, 0};
  gated.stage_ns = kStageNs;
  cases.push_back(one("frame_prediction_gated",
                      "a frame the contact gate skipped: no heads, infer_start_ns = the contact "
                      "decision, infer_end_ns 0 (README §7)",
                      wire(message(gated, 2)), {"ok:frame_prediction"}));
  {
    // Minor 3: the gate's state and score; a frame while the gate learns its reference.
    protocol::FramePrediction calibrating = encoded;
    calibrating.contact = false;
    calibrating.gate = protocol::GateState::kCalibrating;
    calibrating.gate_score_dn = 1.5f;
    ordered_json c = one("frame_prediction_gate",
                         "minor 3: the contact gate's state (calibrating: not decided yet) and "
                         "score in DN; a 1.2 receiver skips both",
                         wire(message(calibrating, 2)), {"ok:frame_prediction"});
    c["fields"] = {{"contact", false}, {"gate", "calibrating"}, {"gate_score_dn", 1.5}};
    cases.push_back(c);
  }
  protocol::GraspPrediction grasp;
  grasp.grasp_id = 3;
  grasp.status = protocol::GraspStatus::kComputed;
  grasp.probability = 0.8125f;
  grasp.phase_source = protocol::PhaseSource::kDetected;
  grasp.closed_ns = 3'000'000'000;
  grasp.infer_end_ns = 3'300'000'000;
  cases.push_back(one("grasp_prediction_detected",
                      "phase_source detected is sent (not the default)", wire(message(grasp, 3)),
                      {"ok:grasp_prediction"}));
  const protocol::DropCount drops[] = {
      {protocol::DropCause::kInferenceBusy, 2, protocol::kNoSensor},
      {protocol::DropCause::kQueueFull, 1, protocol::kNoSensor}};
  protocol::Stats stats;
  stats.uptime_ns = 5'000'000'000;
  stats.drops = drops;
  cases.push_back(one("stats_delayed",
                      "a Stats flagged DELAYED (bit 0): made while the link was down",
                      wire(message(stats, 4, protocol::kFlagDelayed)), {"ok:stats"}));
  protocol::ErrorReport info{0, "info", "camera back", protocol::kNoSensor};
  cases.push_back(one("error_info", "code 0: an informational event, not an error (README §14)",
                      wire(message(info, 5)), {"ok:error"}));
  protocol::ErrorReport bad_text{0, "info", "bad \xff\xfe bytes", protocol::kNoSensor};
  ordered_json utf8 = one("error_text_not_utf8",
                          "a string that is not UTF-8 is delivered with U+FFFD for each bad byte",
                          wire(message(bad_text, 6)), {"ok:error"});
  utf8["fields"] = {{"text", "bad \xEF\xBF\xBD\xEF\xBF\xBD bytes"}};
  cases.push_back(utf8);
  cases.push_back(one("ack", "", wire(message(protocol::Ack{7, protocol::CommandKind::kStart}, 7)),
                      {"ok:ack"}));
  cases.push_back(one(
      "nack", "", wire(message(protocol::Nack{8, protocol::CommandKind::kSetConfig, 513, "no"}, 8)),
      {"ok:nack"}));
  cases.push_back(one("pong", "", wire(message(protocol::Pong{9, 100, 200}, 9)), {"ok:pong"}));
  {
    // Minor 2. The image bytes are not a real JPEG: a receiver delivers them, it does not decode
    // them.
    static const uint8_t kJpeg[] = {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x10, 0xFF, 0xD9};
    static const uint8_t kMask[] = {0x21,
                                    0x80};  // 4x3 cells: (0,0), (1,1), and bit 15 beyond the grid
    protocol::FrameImage image;
    image.sensor = 0;
    image.frame_sequence = 41;
    image.capture_ns = 2'000'000'000;
    image.kind = protocol::ImageKind::kInput;
    image.width = 224;
    image.height = 224;
    image.contact = true;
    image.mask_width = 4;
    image.mask_height = 3;
    image.mask = kMask;
    image.data = kJpeg;
    ordered_json c =
        one("frame_image", "minor 2: a FrameImage; the mask as rows of 0/1, the image base64",
            wire(message(image, 10)), {"ok:frame_image"});
    c["fields"] = {{"kind", "input"},
                   {"format", "jpeg"},
                   {"contact", true},
                   {"mask", {"1000", "0100", "0000"}},
                   {"data", "/9j/4AAQ/9k="}};
    cases.push_back(c);
  }
  const Bytes ack = message(protocol::Ack{7, protocol::CommandKind::kStart}, 10);
  {
    Bytes b = wire(ack), again = wire(message(protocol::Ack{8, protocol::CommandKind::kStop}, 11));
    b.insert(b.end(), again.begin(), again.end());
    cases.push_back(one("two_frames", "two frames back to back", b, {"ok:ack", "ok:ack"}));
  }
  {
    Bytes b = {std::byte{0}, std::byte{0}};
    const Bytes w = wire(ack);
    b.insert(b.end(), w.begin(), w.end());
    b.push_back(std::byte{0});
    cases.push_back(one("empty_segments",
                        "extra delimiters are empty segments: ignored, no verdict", b, {"ok:ack"}));
  }
  {
    FrameHeader minor = header(MessageType::kAck, 12, 0);
    minor.version_minor = 9;
    const Bytes p = payload_of(protocol::Ack{7, protocol::CommandKind::kStart});
    minor.payload_length = static_cast<uint32_t>(p.size());
    cases.push_back(one("newer_minor", "another minor version of the same major is read",
                        wire(body(minor, p)), {"ok:ack"}));
    cases.push_back(one("ignorable_flag", "an unknown flag of bits 0-7 is ignored",
                        wire(message(protocol::Ack{7, protocol::CommandKind::kStart}, 13, 0x0080)),
                        {"ok:ack"}));
    cases.push_back(one("must_understand_flag", "an unknown flag of bits 8-15 rejects the frame",
                        wire(message(protocol::Ack{7, protocol::CommandKind::kStart}, 14, 0x0100)),
                        {"flags"}));
  }
  // Framing and frame verdicts, in the order of README §4.
  {
    ordered_json c = {
        {"name", "oversized_segment"},
        {"note", "a segment over 16,449 bytes is oversized whatever it holds (not decoded)"},
        {"wire", {{{"hex", "11"}, {"repeat", 16450}}, {{"hex", "00"}}}},
        {"expect", {"oversized"}}};
    cases.push_back(c);
    ordered_json d = {{"name", "oversized_decoded"},
                      {"note",
                       "a segment within 16,449 bytes that is valid COBS but decodes to more than "
                       "16,384 bytes (16,449 code bytes 01: 16,448 zeros)"},
                      {"wire", {{{"hex", "01"}, {"repeat", 16449}}, {{"hex", "00"}}}},
                      {"expect", {"oversized"}}};
    cases.push_back(d);
    ordered_json e = {
        {"name", "cobs_before_decoded_size"},
        {"note",
         "a segment within 16,449 bytes whose last code byte runs past its end is cobs, "
         "even if it would decode to more than 16,384 bytes"},
        {"wire", {{{"hex", "01"}, {"repeat", 16440}}, {{"hex", "0511"}}, {{"hex", "00"}}}},
        {"expect", {"cobs"}}};
    cases.push_back(e);
  }
  cases.push_back(one("cobs", "a code byte that runs past the end of the segment",
                      unhex("05112200"), {"cobs"}));
  cases.push_back(one("garbage_then_frame",
                      "garbage before a frame costs only the garbage's segment",
                      [&] {
                        Bytes b = unhex("ff1234560a00");
                        const Bytes w = wire(ack);
                        b.insert(b.end(), w.begin(), w.end());
                        return b;
                      }(),
                      {"cobs", "ok:ack"}));
  cases.push_back(
      one("shorter_than_8", "decodes to fewer than 8 bytes", wire(unhex("544c01")), {"truncated"}));
  {
    // 8..27 bytes: the CRC decides first; a good CRC over a right magic and major but no room
    // for the header is truncated.
    const Bytes ten = unhex("00112233445566778899");
    cases.push_back(one("short_bad_crc", "8 to 27 bytes whose CRC fails: crc (no header to read)",
                        wire(ten), {"crc"}));
    Bytes tl = unhex("544c01000600");
    const uint32_t crc = crc32(tl);
    for (int i = 0; i < 4; ++i) tl.push_back(static_cast<std::byte>((crc >> (8 * i)) & 0xFF));
    cases.push_back(one("short_good_crc",
                        "8 to 27 bytes, CRC fine, magic and major right: truncated", wire(tl),
                        {"truncated"}));
  }
  {
    Bytes cut = ack;
    cut.resize(cut.size() - 10);
    cases.push_back(one("cut_short",
                        "CRC fails and the header says more payload than there is: truncated",
                        wire(cut), {"truncated"}));
    Bytes flipped = ack;
    flipped[30] ^= std::byte{0x04};
    cases.push_back(one("bit_flip", "one payload bit flipped: crc", wire(flipped), {"crc"}));
    Bytes version = ack;
    version[2] ^= std::byte{0x03};
    cases.push_back(one("version_byte_flipped",
                        "a corrupted version byte is a CRC error, not a refusal", wire(version),
                        {"crc"}));
  }
  {
    const Bytes p = payload_of(protocol::Ack{7, protocol::CommandKind::kStart});
    FrameHeader h = header(MessageType::kAck, 15, p.size());
    Bytes magic = body(h, p);
    magic[0] = std::byte{'X'};
    const Bytes magic_body(magic.begin(), magic.end() - 4);
    Bytes recrc = magic_body;
    const uint32_t crc = crc32(magic_body);
    for (int i = 0; i < 4; ++i) recrc.push_back(static_cast<std::byte>((crc >> (8 * i)) & 0xFF));
    cases.push_back(one("magic", "CRC fine, not \"TL\"", wire(recrc), {"magic"}));
    FrameHeader v2 = h;
    v2.version_major = 2;
    cases.push_back(
        one("major_2", "CRC fine, another major version: refused", wire(body(v2, p)), {"version"}));
    FrameHeader longer = h;
    longer.payload_length = static_cast<uint32_t>(p.size() + 4);
    cases.push_back(one("length_longer", "CRC fine, the header's payload length is not the frame's",
                        wire(body(longer, p)), {"length"}));
  }
  // Good frames a host skips.
  {
    const Bytes p = payload_of(protocol::Ack{7, protocol::CommandKind::kStart});
    cases.push_back(
        one("unknown_type", "a type this reader does not know (0x0042): skipped, counted",
            wire(body(header(static_cast<MessageType>(0x42), 16, p.size()), p)), {"unknown_type"}));
    protocol::Command cmd;
    cmd.kind = protocol::CommandKind::kPing;
    cases.push_back(one("command_to_host",
                        "a command frame reaching a host: skipped like an unknown type",
                        wire(message(cmd, 17)), {"unknown_type"}));
    const Bytes junk = unhex("ffffff7f00000000");
    cases.push_back(one("undecodable", "an Ack whose payload's root offset points outside it",
                        wire(body(header(MessageType::kAck, 18, junk.size()), junk)),
                        {"undecodable"}));
  }
  return cases;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string render(const ordered_json& cases) {
  ordered_json doc = {{"format", "tlvlink stream conformance cases, README section 16"},
                      {"protocol", std::to_string(protocol::kVersionMajor) + "." +
                                       std::to_string(protocol::kVersionMinor)},
                      {"cases", cases}};
  return doc.dump(1, ' ', false) + "\n";
}

TEST(Conformance, TheCheckedInCasesAreWhatThisCodeMakes) {
  const std::string made = render(make_cases());
  if (const char* r = std::getenv("TLVLINK_REGENERATE_CONFORMANCE");
      r != nullptr && std::string(r) == "1") {
    std::ofstream(kCasesPath, std::ios::binary) << made;
  }
  EXPECT_EQ(slurp(kCasesPath), made)
      << "runtime/protocol/conformance/cases.json is out of date: after a deliberate change, run "
         "this test with TLVLINK_REGENERATE_CONFORMANCE=1 and review the diff";
}

// What a tlvlink host makes of one segment (client_frames.cc): a verdict, or for a good frame
// "ok:TYPE", "unknown_type" or "undecodable".
std::string outcome(const protocol::ReceivedFrame& f) {
  if (f.verdict == protocol::FrameVerdict::kUnsupportedFlags) return "flags";
  if (f.verdict != protocol::FrameVerdict::kOk) return protocol::frame_verdict_name(f.verdict);
  const char* type = protocol::message_type_name(f.header.type);
  if (type == nullptr || f.header.type == MessageType::kCommand) return "unknown_type";
  if (!protocol::verify_payload(f.header.type, f.payload).ok()) return "undecodable";
  return std::string("ok:") + type;
}

TEST(Conformance, EveryCaseGetsItsOutcome) {
  const auto doc = nlohmann::json::parse(slurp(kCasesPath));
  ASSERT_GE(doc.at("cases").size(), 25u);
  for (const auto& c : doc.at("cases")) {
    Bytes bytes;
    for (const auto& part : c.at("wire")) {
      const Bytes b = unhex(part.at("hex").get<std::string>());
      for (int k = 0; k < part.value("repeat", 1); ++k)
        bytes.insert(bytes.end(), b.begin(), b.end());
    }
    static protocol::Deframer deframer;
    deframer.reset();
    std::vector<std::string> got;
    deframer.feed(bytes, [&](const protocol::ReceivedFrame& f) {
      got.push_back(outcome(f));
      if (!c.contains("fields") || f.verdict != protocol::FrameVerdict::kOk) return;
      const auto line = nlohmann::json::parse(json_line(Message(f.header, f.payload, 0), {}));
      for (const auto& [key, value] : c.at("fields").items())
        EXPECT_EQ(line.at(key), value) << c.at("name");
    });
    EXPECT_EQ(got, c.at("expect").get<std::vector<std::string>>())
        << c.at("name") << ": " << c.at("note");
  }
}

}  // namespace
}  // namespace tlvlink::listen
