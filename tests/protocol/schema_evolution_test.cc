// Schema evolution inside major version 1: a newer peer's extra fields are skipped, an older
// peer's missing fields read as defaults, unknown enum values and message types are reported as
// such, never misread. Payloads are built field by field with the flatbuffers builder, as a peer
// with another version of stream.fbs would build them.
#include <gtest/gtest.h>

#include <flatbuffers/flatbuffers.h>

#include <cmath>

#include "stream_generated.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {

namespace fb = tlvlink::wire;

// Slot n of a table (flatbuffers voffset of its n-th field).
constexpr flatbuffers::voffset_t slot(int n) {
  return static_cast<flatbuffers::voffset_t>(4 + 2 * n);
}

std::span<const std::byte> bytes(const flatbuffers::FlatBufferBuilder& fbb) {
  return {reinterpret_cast<const std::byte*>(fbb.GetBufferPointer()), fbb.GetSize()};
}

TEST(SchemaEvolution, FieldsFromANewerPeerAreSkipped) {
  flatbuffers::FlatBufferBuilder fbb;
  const auto future_text = fbb.CreateString("a field this reader does not know");
  const fb::FrameTiming timing(11, 22, 33);
  const auto start = fbb.StartTable();
  fbb.AddElement<uint8_t>(fb::FramePrediction::VT_SENSOR, 1, 0);
  fbb.AddElement<uint32_t>(fb::FramePrediction::VT_FRAME_SEQUENCE, 77, 0);
  fbb.AddStruct(fb::FramePrediction::VT_TIMING, &timing);
  fbb.AddElement<uint8_t>(fb::FramePrediction::VT_CONTACT, 1, 0);
  fbb.AddElement<uint8_t>(fb::FramePrediction::VT_GATE, 3, 0);
  // FramePrediction has 9 fields (slots 0-8, 1.3); a newer minor version appended three more.
  fbb.AddElement<uint64_t>(slot(9), 0xDEADBEEFCAFEull, 0);
  fbb.AddOffset(slot(10), future_text);
  fbb.AddElement<float>(slot(11), 3.5f, 0);
  fbb.Finish(flatbuffers::Offset<fb::FramePrediction>(fbb.EndTable(start)));
  Result<FramePredictionView> r = decode_frame_prediction(bytes(fbb));
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r.value().sensor(), 1);
  EXPECT_EQ(r.value().frame_sequence(), 77u);
  EXPECT_EQ(r.value().timing().infer_end_ns, 33);
  EXPECT_TRUE(r.value().contact());
  EXPECT_EQ(r.value().head_count(), 0u);
  EXPECT_TRUE(r.value().embedding().empty());
  EXPECT_EQ(r.value().gate(), GateState::kContact);
}

// A board of protocol 1.2 sends no gate state: unknown and NaN, and `contact` as it was.
TEST(SchemaEvolution, FramePredictionOfA12BoardHasNoGateState) {
  flatbuffers::FlatBufferBuilder fbb;
  const auto start = fbb.StartTable();
  fbb.AddElement<uint32_t>(fb::FramePrediction::VT_FRAME_SEQUENCE, 5, 0);
  fbb.AddElement<uint8_t>(fb::FramePrediction::VT_CONTACT, 1, 0);
  fbb.Finish(flatbuffers::Offset<fb::FramePrediction>(fbb.EndTable(start)));
  Result<FramePredictionView> r = decode_frame_prediction(bytes(fbb));
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_TRUE(r.value().contact());
  EXPECT_EQ(r.value().gate(), GateState::kUnknown);
  EXPECT_STREQ(gate_state_name(r.value().gate()), "unknown");
  EXPECT_TRUE(std::isnan(r.value().gate_score_dn()));
}

TEST(SchemaEvolution, FieldsAnOlderPeerDidNotSendReadAsDefaults) {
  flatbuffers::FlatBufferBuilder fbb;
  const auto device = fbb.CreateString("old-board");
  const auto start = fbb.StartTable();
  fbb.AddOffset(fb::Hello::VT_DEVICE, device);
  fbb.AddElement<uint64_t>(fb::Hello::VT_BOOT_ID, 5, 0);
  fbb.Finish(flatbuffers::Offset<fb::Hello>(fbb.EndTable(start)));
  Result<HelloView> r = decode_hello(bytes(fbb));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().device(), "old-board");
  EXPECT_EQ(r.value().boot_id(), 5u);
  EXPECT_EQ(r.value().board(), "");
  EXPECT_EQ(r.value().head_count(), 0u);
  EXPECT_EQ(r.value().max_frame_size(), 0u) << "absent: the reader assumes the protocol maximum";
  EXPECT_EQ(r.value().schema_hash(), 0u);
}

TEST(SchemaEvolution, UnknownEnumValuesAreKeptAsNumbers) {
  flatbuffers::FlatBufferBuilder fbb;
  const auto start = fbb.StartTable();
  fbb.AddElement<uint8_t>(fb::Command::VT_KIND, 42, 0);
  fbb.Finish(flatbuffers::Offset<fb::Command>(fbb.EndTable(start)));
  Result<Command> r = decode_command(bytes(fbb));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(static_cast<int>(r.value().kind), 42);
  EXPECT_EQ(command_kind_name(r.value().kind), nullptr);
  EXPECT_EQ(r.value().sensor, kNoSensor);
}

TEST(SchemaEvolution, UnknownMessageTypeIsUnsupportedNotMalformed) {
  flatbuffers::FlatBufferBuilder fbb;
  fbb.Finish(flatbuffers::Offset<fb::Ack>(fbb.EndTable(fbb.StartTable())));
  const Status s = verify_payload(static_cast<MessageType>(0x42), bytes(fbb));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kProtocolUnsupported);
}

}  // namespace
}  // namespace tlvlink::protocol
