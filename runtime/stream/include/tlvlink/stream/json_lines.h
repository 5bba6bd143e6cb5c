#pragma once
// The stream's messages as JSON lines: one object per message, the keys and value formats of
// `tlvlink listen --json` (tools/listen/README.md lists them), written into a LineBuffer without
// allocating. A board writes its own lines with these (tlvlinkd's `jsonl:` output), the listener
// writes what it received with them, and `tlvlink score` reads either.
//
// A line is json_begin (type and the frame header's fields), json_fields of the message, any
// fields of the writer's own (the listener's host clock, the daemon's run report), json_end.
// Enum values print by name, or as their number when this build does not know them; NaN as null.

#include <cstdint>

#include "tlvlink/protocol/messages.h"
#include "tlvlink/stream/line_buffer.h"

namespace tlvlink::stream {

// The frame header's fields a line carries. A board writing lines without a link numbers its
// lines from 0 and stamps when it wrote each one, as its link would.
struct JsonHeader {
  uint32_t sequence = 0;
  uint16_t flags = 0;
  int64_t send_ns = 0;
};

// {"type":..,"sequence":..,"flags":..,"delayed":..,"send_ns":..  (the object stays open)
void json_begin(LineBuffer& out, protocol::MessageType type, const JsonHeader& header);
// `schema_hash`: the sender's (schema_matches compares it with this build's).
void json_fields(LineBuffer& out, const protocol::Hello& m, uint64_t schema_hash);
// `names`: the Hello the frame follows, for sensor_name and the heads' name and top_label
// (left out without one).
void json_fields(LineBuffer& out, const protocol::FramePrediction& m, const protocol::Hello* names);
void json_fields(LineBuffer& out, const protocol::GraspPrediction& m);
void json_fields(LineBuffer& out, const protocol::Stats& m);
void json_fields(LineBuffer& out, const protocol::ErrorReport& m);
void json_fields(LineBuffer& out, const protocol::Ack& m);
void json_fields(LineBuffer& out, const protocol::Nack& m);
void json_fields(LineBuffer& out, const protocol::Pong& m);
// }\n
void json_end(LineBuffer& out);

}  // namespace tlvlink::stream
