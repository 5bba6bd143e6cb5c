"""The payload schema (runtime/protocol/schema/stream.fbs) as this package reads it: each table's
fields in slot order, the enums' names, the message type numbers and the schema hash this
package was written against. tests/test_schema.py checks all of it against stream.fbs."""

from __future__ import annotations

import hashlib
import re

# Hash of the stream.fbs this package decodes (README "Schema hash"). A Hello carries the board's;
# a different value means fields may be unknown to one side (they are skipped), not an error.
SCHEMA_HASH = 0xd42d83f639579b4a

MESSAGE_TYPES = {
    0x01: "hello",
    0x02: "frame_prediction",
    0x03: "grasp_prediction",
    0x04: "stats",
    0x05: "error",
    0x06: "ack",
    0x07: "nack",
    0x08: "pong",
    0x09: "frame_image",
    0x80: "command",
}
MESSAGE_TYPE_NUMBERS = {name: number for number, name in MESSAGE_TYPES.items()}

# Fields of every table, in slot order (slot n is vtable entry n).
TABLES = {
    "SensorInfo": ["index", "name", "model", "serial", "pixel_format", "width", "height", "fps"],
    "HeadInfo": ["name", "kind", "labels", "accuracy", "majority_rate", "accuracy_ci_low", "accuracy_ci_high",
                 "balanced_accuracy", "baseline_accuracy", "groups"],
    "Hello": ["device", "board", "firmware_version", "boot_id", "schema_hash", "model_id", "model_checksum",
              "sensors", "heads", "stage_names", "embedding_dim", "clock", "max_frame_size"],
    "HeadOutput": ["head", "probabilities"],
    "FramePrediction": ["sensor", "frame_sequence", "timing", "stage_ns", "contact", "heads", "embedding", "gate",
                        "gate_score_dn"],
    "GraspPrediction": ["grasp_id", "status", "probability", "reason", "reason_text", "frames", "phase_source",
                        "closed_ns", "lifting_ns", "infer_end_ns"],
    "DropCount": ["cause", "count", "sensor"],
    "SensorStats": ["sensor", "fps", "frames", "inferred", "gated"],
    "LinkStats": ["link_up", "reconnects", "frames_sent", "bytes_sent", "frames_received", "frames_rejected",
                  "queue_messages", "queue_bytes", "queue_capacity_bytes"],
    "Stats": ["uptime_ns", "sensors", "drops", "cpu_percent", "cpu_cores", "rss_bytes", "link"],
    "ErrorReport": ["code", "name", "text", "sensor"],
    "Ack": ["command_sequence", "kind"],
    "Nack": ["command_sequence", "kind", "code", "text"],
    "Pong": ["command_sequence", "host_send_ns", "board_receive_ns"],
    "FrameImage": ["sensor", "frame_sequence", "capture_ns", "kind", "width", "height", "format", "contact",
                   "mask_width", "mask_height", "mask", "data"],
    "Command": ["kind", "sensor", "grasp_id", "event_ns", "key", "value", "clock_offset_ns", "clock_uncertainty_ns"],
}
STRUCTS = {
    "FrameTiming": ["capture_ns", "infer_start_ns", "infer_end_ns"],
    "GraspFrame": ["sensor", "phase", "frame_sequence", "capture_ns"],
}


def slot(table: str, field: str) -> int:
    return TABLES[table].index(field)


# Enum value names, index = value (the C++ names.h names).
ENUMS = {
    "CommandKind": ["none", "start", "stop", "grasp_closed", "grasp_lifting", "rezero", "set_config", "info", "ping",
                    "time_sync"],
    "HeadKind": ["linear", "zero_shot", "grasp"],
    "GraspStatus": ["computed", "not_computed"],
    "GraspReason": ["none", "missing_finger", "late_finger", "no_contact", "no_grasp_head", "phase_timeout", "aborted",
                    "other"],
    "GraspPhase": ["before", "during"],
    "PhaseSource": ["command", "detected"],
    "DropCause": ["capture_gap", "capture_error", "inference_busy", "queue_full", "link_down", "stale", "image_busy"],
    "GateState": ["unknown", "calibrating", "none", "contact"],
    "ImageKind": ["view", "input"],
    "ImageFormat": ["jpeg"],
}


def enum_name(enum: str, value: int):
    """The value's name, or the number itself when this package does not know it (a newer board)."""
    names = ENUMS[enum]
    return names[value] if 0 <= value < len(names) else value


def schema_hash_of(fbs_text: str) -> int:
    """SHA-256 of the schema text without // comments, whitespace runs collapsed to one space and
    the ends trimmed; the first 8 bytes as a big-endian number."""
    text = re.sub(r"//[^\n]*", "", fbs_text)
    text = re.sub(r"[ \t\r\n]+", " ", text).strip()
    return int.from_bytes(hashlib.sha256(text.encode("utf-8")).digest()[:8], "big")
