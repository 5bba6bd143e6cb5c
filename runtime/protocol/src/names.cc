#include "tlvlink/protocol/names.h"

#include <cstring>

namespace tlvlink::protocol {

const char* message_type_name(MessageType type) {
  switch (type) {
    case MessageType::kHello: return "hello";
    case MessageType::kFramePrediction: return "frame_prediction";
    case MessageType::kGraspPrediction: return "grasp_prediction";
    case MessageType::kStats: return "stats";
    case MessageType::kError: return "error";
    case MessageType::kAck: return "ack";
    case MessageType::kNack: return "nack";
    case MessageType::kPong: return "pong";
    case MessageType::kFrameImage: return "frame_image";
    case MessageType::kCommand: return "command";
  }
  return nullptr;
}

const char* head_kind_name(HeadKind kind) {
  switch (kind) {
    case HeadKind::kLinear: return "linear";
    case HeadKind::kZeroShot: return "zero_shot";
    case HeadKind::kGrasp: return "grasp";
  }
  return nullptr;
}

const char* grasp_status_name(GraspStatus status) {
  switch (status) {
    case GraspStatus::kComputed: return "computed";
    case GraspStatus::kNotComputed: return "not_computed";
  }
  return nullptr;
}

const char* grasp_reason_name(GraspReason reason) {
  switch (reason) {
    case GraspReason::kNone: return "none";
    case GraspReason::kMissingFinger: return "missing_finger";
    case GraspReason::kLateFinger: return "late_finger";
    case GraspReason::kNoContact: return "no_contact";
    case GraspReason::kNoGraspHead: return "no_grasp_head";
    case GraspReason::kPhaseTimeout: return "phase_timeout";
    case GraspReason::kAborted: return "aborted";
    case GraspReason::kOther: return "other";
  }
  return nullptr;
}

const char* grasp_phase_name(GraspPhase phase) {
  switch (phase) {
    case GraspPhase::kBefore: return "before";
    case GraspPhase::kDuring: return "during";
  }
  return nullptr;
}

const char* phase_source_name(PhaseSource source) {
  switch (source) {
    case PhaseSource::kCommand: return "command";
    case PhaseSource::kDetected: return "detected";
  }
  return nullptr;
}

const char* drop_cause_name(DropCause cause) {
  switch (cause) {
    case DropCause::kCaptureGap: return "capture_gap";
    case DropCause::kCaptureError: return "capture_error";
    case DropCause::kInferenceBusy: return "inference_busy";
    case DropCause::kQueueFull: return "queue_full";
    case DropCause::kLinkDown: return "link_down";
    case DropCause::kStale: return "stale";
    case DropCause::kImageBusy: return "image_busy";
  }
  return nullptr;
}

const char* gate_state_name(GateState state) {
  switch (state) {
    case GateState::kUnknown: return "unknown";
    case GateState::kCalibrating: return "calibrating";
    case GateState::kNone: return "none";
    case GateState::kContact: return "contact";
  }
  return nullptr;
}

const char* image_kind_name(ImageKind kind) {
  switch (kind) {
    case ImageKind::kView: return "view";
    case ImageKind::kInput: return "input";
  }
  return nullptr;
}

const char* image_format_name(ImageFormat format) {
  switch (format) {
    case ImageFormat::kJpeg: return "jpeg";
  }
  return nullptr;
}

const char* command_kind_name(CommandKind kind) {
  switch (kind) {
    case CommandKind::kNone: return "none";
    case CommandKind::kStart: return "start";
    case CommandKind::kStop: return "stop";
    case CommandKind::kGraspClosed: return "grasp_closed";
    case CommandKind::kGraspLifting: return "grasp_lifting";
    case CommandKind::kRezero: return "rezero";
    case CommandKind::kSetConfig: return "set_config";
    case CommandKind::kInfo: return "info";
    case CommandKind::kPing: return "ping";
    case CommandKind::kTimeSync: return "time_sync";
  }
  return nullptr;
}

bool command_kind_from_name(const char* name, CommandKind& kind) {
  for (int k = 1; k <= static_cast<int>(CommandKind::kTimeSync); ++k) {
    const char* n = command_kind_name(static_cast<CommandKind>(k));
    if (n != nullptr && std::strcmp(n, name) == 0) {
      kind = static_cast<CommandKind>(k);
      return true;
    }
  }
  return false;
}

}  // namespace tlvlink::protocol
