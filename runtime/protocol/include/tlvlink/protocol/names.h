#pragma once
// Stable lower-case names of the protocol's enums, as the listeners print them and the JSON
// lines carry them ("frame_prediction", "queue_full", "grasp_closed"). A value this build does
// not know gives nullptr: callers print the number.

#include <cstdint>

#include "tlvlink/protocol/messages.h"
#include "tlvlink/protocol/wire.h"

namespace tlvlink::protocol {

const char* message_type_name(MessageType type);
const char* head_kind_name(HeadKind kind);
const char* grasp_status_name(GraspStatus status);
const char* grasp_reason_name(GraspReason reason);
const char* grasp_phase_name(GraspPhase phase);
const char* phase_source_name(PhaseSource source);
const char* drop_cause_name(DropCause cause);
const char* gate_state_name(GateState state);       // "unknown", "calibrating", "none", "contact"
const char* image_kind_name(ImageKind kind);        // "view", "input"
const char* image_format_name(ImageFormat format);  // "jpeg"
const char* command_kind_name(CommandKind kind);
// The inverse for commands typed by people ("start", "grasp_closed"); false if unknown.
bool command_kind_from_name(const char* name, CommandKind& kind);

}  // namespace tlvlink::protocol
