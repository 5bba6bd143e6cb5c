"""The stream's messages as Python objects. decode(type, payload) reads a payload (bounds-checked,
fields unknown to this package skipped, absent fields at their defaults); Message.to_dict() gives
the same keys and values as the C++ `tlvlink listen --json` lines (tools/listen/README.md)."""

from __future__ import annotations

import base64
import math
import struct
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

from . import schema
from .flatbuf import DecodeError, Table
from .schema import enum_name, slot

NAN = float("nan")


def _f(t: Table, table: str, name: str, fmt: str, default=0):
    return t.scalar(slot(table, name), fmt, default)


def _s(t: Table, table: str, name: str) -> str:
    return t.string(slot(table, name))


def _float_or_none(v: float):
    return None if math.isnan(v) else v


@dataclass
class SensorInfo:
    index: int
    name: str
    model: str
    serial: str
    pixel_format: str
    width: int
    height: int
    fps: float


@dataclass
class HeadInfo:
    name: str
    kind: Any
    labels: List[str]
    accuracy: float = NAN        # NaN: not recorded in the model file
    majority_rate: float = NAN
    # minor 1: a head fitted by grouped cross-validation (NaN / 0: not recorded)
    accuracy_ci_low: float = NAN
    accuracy_ci_high: float = NAN
    balanced_accuracy: float = NAN
    baseline_accuracy: float = NAN
    groups: int = 0


@dataclass
class Hello:
    device: str
    board: str
    firmware_version: str
    boot_id: int
    schema_hash: int
    model_id: str
    model_checksum: int
    sensors: List[SensorInfo]
    heads: List[HeadInfo]
    stage_names: List[str]
    embedding_dim: int
    clock: str
    max_frame_size: int

    def sensor_name(self, index: int) -> str:
        for s in self.sensors:
            if s.index == index:
                return s.name
        return ""


@dataclass
class HeadOutput:
    head: int
    probabilities: List[float]


@dataclass
class FramePrediction:
    sensor: int
    frame_sequence: int
    capture_ns: int
    infer_start_ns: int
    infer_end_ns: int
    stage_ns: List[int]
    contact: bool
    heads: List[HeadOutput]
    embedding: List[float]
    gate: Any = "unknown"  # minor 3: the contact gate's state; "unknown" from an older board
    gate_score_dn: float = math.nan  # minor 3: the gate's score, DN; NaN from an older board


@dataclass
class GraspFrame:
    sensor: int
    phase: Any
    frame_sequence: int
    capture_ns: int


@dataclass
class GraspPrediction:
    grasp_id: int
    status: Any
    probability: float  # NaN unless computed
    reason: Any
    reason_text: str
    frames: List[GraspFrame]
    phase_source: Any
    closed_ns: int
    lifting_ns: int
    infer_end_ns: int


@dataclass
class Stats:
    uptime_ns: int
    sensors: List[Dict[str, Any]]
    drops: List[Dict[str, Any]]
    cpu_percent: float
    cpu_cores: int
    rss_bytes: int
    link: Dict[str, Any]


@dataclass
class ErrorReport:
    code: int
    name: str
    text: str
    sensor: int


@dataclass
class Ack:
    command_sequence: int
    kind: Any


@dataclass
class Nack:
    command_sequence: int
    kind: Any
    code: int
    text: str


@dataclass
class Pong:
    command_sequence: int
    host_send_ns: int
    board_receive_ns: int


@dataclass
class FrameImage:
    sensor: int
    frame_sequence: int
    capture_ns: int
    kind: Any          # "view" | "input"
    width: int
    height: int
    format: Any        # "jpeg"
    contact: bool
    mask_width: int    # contact mask cells across and down (0 = no mask)
    mask_height: int
    mask: bytes        # 1 bit per cell, row-major, bit i in byte i // 8 at (1 << i % 8)
    data: bytes        # the JPEG file

    def mask_cell(self, x: int, y: int) -> bool:
        i = y * self.mask_width + x
        return i // 8 < len(self.mask) and bool((self.mask[i // 8] >> (i % 8)) & 1)

    def mask_rows(self) -> List[str]:
        """The mask as the listeners print it: one string of 0/1 per row of cells."""
        return ["".join("1" if self.mask_cell(x, y) else "0" for x in range(self.mask_width))
                for y in range(self.mask_height)]


def _hello(t: Table) -> Hello:
    T = "Hello"
    sensors = []
    for s in t.tables(slot(T, "sensors")):
        S = "SensorInfo"
        sensors.append(SensorInfo(_f(s, S, "index", "B"), _s(s, S, "name"), _s(s, S, "model"), _s(s, S, "serial"),
                                  _s(s, S, "pixel_format"), _f(s, S, "width", "H"), _f(s, S, "height", "H"),
                                  _f(s, S, "fps", "f", 0.0)))
    heads = []
    for h in t.tables(slot(T, "heads")):
        H = "HeadInfo"
        heads.append(HeadInfo(_s(h, H, "name"), enum_name("HeadKind", _f(h, H, "kind", "B")),
                              h.strings(slot(H, "labels")), _f(h, H, "accuracy", "f", NAN),
                              _f(h, H, "majority_rate", "f", NAN), _f(h, H, "accuracy_ci_low", "f", NAN),
                              _f(h, H, "accuracy_ci_high", "f", NAN), _f(h, H, "balanced_accuracy", "f", NAN),
                              _f(h, H, "baseline_accuracy", "f", NAN), _f(h, H, "groups", "I")))
    return Hello(_s(t, T, "device"), _s(t, T, "board"), _s(t, T, "firmware_version"), _f(t, T, "boot_id", "Q"),
                 _f(t, T, "schema_hash", "Q"), _s(t, T, "model_id"), _f(t, T, "model_checksum", "Q"), sensors, heads,
                 t.strings(slot(T, "stage_names")), _f(t, T, "embedding_dim", "H"), _s(t, T, "clock"),
                 _f(t, T, "max_frame_size", "I"))


def _frame(t: Table) -> FramePrediction:
    T = "FramePrediction"
    timing = t.struct_at(slot(T, "timing"), 24)
    capture, start, end = struct.unpack_from("<qqq", t.buf, timing) if timing is not None else (0, 0, 0)
    heads = [HeadOutput(_f(h, "HeadOutput", "head", "H"), h.scalars(slot("HeadOutput", "probabilities"), "f"))
             for h in t.tables(slot(T, "heads"))]
    return FramePrediction(_f(t, T, "sensor", "B"), _f(t, T, "frame_sequence", "I"), capture, start, end,
                           t.scalars(slot(T, "stage_ns"), "I"), bool(_f(t, T, "contact", "B")), heads,
                           t.scalars(slot(T, "embedding"), "f"), enum_name("GateState", _f(t, T, "gate", "B")),
                           _f(t, T, "gate_score_dn", "f", math.nan))


def _grasp(t: Table) -> GraspPrediction:
    T = "GraspPrediction"
    frames = []
    for p in t.structs(slot(T, "frames"), 16):
        sensor, phase, seq, capture = struct.unpack_from("<BBxxIq", t.buf, p)
        frames.append(GraspFrame(sensor, enum_name("GraspPhase", phase), seq, capture))
    return GraspPrediction(_f(t, T, "grasp_id", "I"), enum_name("GraspStatus", _f(t, T, "status", "B")),
                           _f(t, T, "probability", "f", NAN), enum_name("GraspReason", _f(t, T, "reason", "B")),
                           _s(t, T, "reason_text"), frames, enum_name("PhaseSource", _f(t, T, "phase_source", "B")),
                           _f(t, T, "closed_ns", "q"), _f(t, T, "lifting_ns", "q"), _f(t, T, "infer_end_ns", "q"))


def _stats(t: Table) -> Stats:
    T = "Stats"
    S, D, L = "SensorStats", "DropCount", "LinkStats"
    sensors = [{"sensor": _f(s, S, "sensor", "B"), "fps": _f(s, S, "fps", "f", 0.0), "frames": _f(s, S, "frames", "Q"),
                "inferred": _f(s, S, "inferred", "Q"), "gated": _f(s, S, "gated", "Q")}
               for s in t.tables(slot(T, "sensors"))]
    drops = [{"cause": enum_name("DropCause", _f(d, D, "cause", "B")), "count": _f(d, D, "count", "Q"),
              "sensor": _f(d, D, "sensor", "B", 255)} for d in t.tables(slot(T, "drops"))]
    l = t.table(slot(T, "link"))
    link = {}
    for name in schema.TABLES[L]:
        fmt = {"link_up": "B", "reconnects": "I", "queue_messages": "I", "queue_bytes": "I",
               "queue_capacity_bytes": "I"}.get(name, "Q")
        v = _f(l, L, name, fmt) if l is not None else 0
        link[name] = bool(v) if name == "link_up" else v
    return Stats(_f(t, T, "uptime_ns", "q"), sensors, drops, _f(t, T, "cpu_percent", "f", NAN), _f(t, T, "cpu_cores", "B"),
                 _f(t, T, "rss_bytes", "Q"), link)


def _error(t: Table) -> ErrorReport:
    T = "ErrorReport"
    return ErrorReport(_f(t, T, "code", "H"), _s(t, T, "name"), _s(t, T, "text"), _f(t, T, "sensor", "B", 255))


def _ack(t: Table) -> Ack:
    return Ack(_f(t, "Ack", "command_sequence", "I"), enum_name("CommandKind", _f(t, "Ack", "kind", "B")))


def _nack(t: Table) -> Nack:
    T = "Nack"
    return Nack(_f(t, T, "command_sequence", "I"), enum_name("CommandKind", _f(t, T, "kind", "B")),
                _f(t, T, "code", "H"), _s(t, T, "text"))


def _pong(t: Table) -> Pong:
    T = "Pong"
    return Pong(_f(t, T, "command_sequence", "I"), _f(t, T, "host_send_ns", "q"), _f(t, T, "board_receive_ns", "q"))


def _frame_image(t: Table) -> FrameImage:
    T = "FrameImage"
    return FrameImage(_f(t, T, "sensor", "B"), _f(t, T, "frame_sequence", "I"), _f(t, T, "capture_ns", "q"),
                      enum_name("ImageKind", _f(t, T, "kind", "B")), _f(t, T, "width", "H"), _f(t, T, "height", "H"),
                      enum_name("ImageFormat", _f(t, T, "format", "B")), bool(_f(t, T, "contact", "B")),
                      _f(t, T, "mask_width", "B"), _f(t, T, "mask_height", "B"),
                      t.bytes_vector(slot(T, "mask")), t.bytes_vector(slot(T, "data")))


_DECODERS = {"hello": _hello, "frame_prediction": _frame, "grasp_prediction": _grasp, "stats": _stats,
             "error": _error, "ack": _ack, "nack": _nack, "pong": _pong,
             "frame_image": _frame_image}


def decode(type_name: str, payload: bytes):
    """The body of a board -> host message; DecodeError when the payload is not valid."""
    try:
        return _DECODERS[type_name](Table.root(payload))
    except (struct.error, IndexError) as e:
        raise DecodeError(str(e)) from e


@dataclass
class ClockSnapshot:
    """The client's clock estimate when a message arrived (host = board - offset_ns)."""
    valid: bool = False
    offset_ns: int = 0
    uncertainty_ns: int = 0


@dataclass
class Message:
    """One message as the host received it: header fields, the host receive time
    (time.monotonic_ns(), or as recorded), the clock estimate then, and the decoded body."""
    type: str
    sequence: int
    flags: int
    send_ns: int
    receive_ns: int
    body: Any
    clock: ClockSnapshot = field(default_factory=ClockSnapshot)

    @property
    def delayed(self) -> bool:
        return bool(self.flags & 0x0001)

    def to_host_ns(self, board_ns: int) -> int:
        return board_ns - self.clock.offset_ns if self.clock.valid else board_ns

    def __getattr__(self, name: str):
        # msg.sensor, msg.heads, ...: the body's fields.
        if name == "body":
            raise AttributeError(name)
        return getattr(self.body, name)

    def to_dict(self, hello: Optional[Hello] = None) -> Dict[str, Any]:
        # The keys of the one JSON-lines form (runtime/stream json_lines.h), in its order: the
        # message's, then the host's (receive time, host-clock times, the round trip).
        d: Dict[str, Any] = {"type": self.type, "sequence": self.sequence, "flags": self.flags,
                             "delayed": self.delayed, "send_ns": self.send_ns}
        b = self.body
        if self.type == "hello":
            d.update(device=b.device, board=b.board, firmware_version=b.firmware_version, boot_id=f"{b.boot_id:016x}",
                     schema_hash=f"{b.schema_hash:016x}", schema_matches=b.schema_hash == schema.SCHEMA_HASH,
                     model_id=b.model_id, model_checksum=f"{b.model_checksum:016x}",
                     sensors=[vars(s).copy() for s in b.sensors],
                     heads=[{"name": h.name, "kind": h.kind, "labels": list(h.labels),
                             "accuracy": _float_or_none(h.accuracy), "majority_rate": _float_or_none(h.majority_rate),
                             "accuracy_ci95": [_float_or_none(h.accuracy_ci_low), _float_or_none(h.accuracy_ci_high)],
                             "balanced_accuracy": _float_or_none(h.balanced_accuracy),
                             "baseline_accuracy": _float_or_none(h.baseline_accuracy), "groups": h.groups}
                            for h in b.heads],
                     stage_names=list(b.stage_names), embedding_dim=b.embedding_dim, clock=b.clock,
                     max_frame_size=b.max_frame_size)
        elif self.type == "frame_prediction":
            d["sensor"] = b.sensor
            name = hello.sensor_name(b.sensor) if hello else ""
            if name:
                d["sensor_name"] = name
            d.update(frame_sequence=b.frame_sequence, capture_ns=b.capture_ns, infer_start_ns=b.infer_start_ns,
                     infer_end_ns=b.infer_end_ns)
            d["stage_ns"] = list(b.stage_ns)
            d["contact"] = b.contact
            d["gate"] = b.gate
            d["gate_score_dn"] = _float_or_none(b.gate_score_dn)
            heads = []
            for h in b.heads:
                o: Dict[str, Any] = {"head": h.head}
                named = hello is not None and h.head < len(hello.heads)
                if named:
                    o["name"] = hello.heads[h.head].name
                o["probabilities"] = list(h.probabilities)
                if h.probabilities:
                    top = max(range(len(h.probabilities)), key=lambda k: (h.probabilities[k], -k))
                    if named and top < len(hello.heads[h.head].labels):
                        o["top_label"] = hello.heads[h.head].labels[top]
                    o["top_probability"] = h.probabilities[top]
                heads.append(o)
            d["heads"] = heads
            if b.embedding:
                d["embedding"] = list(b.embedding)
        elif self.type == "grasp_prediction":
            d.update(grasp_id=b.grasp_id, status=b.status, probability=_float_or_none(b.probability), reason=b.reason,
                     reason_text=b.reason_text, frames=[vars(f).copy() for f in b.frames], phase_source=b.phase_source,
                     closed_ns=b.closed_ns, lifting_ns=b.lifting_ns, infer_end_ns=b.infer_end_ns)
        elif self.type == "stats":
            d.update(uptime_ns=b.uptime_ns, sensors=b.sensors, drops=b.drops, cpu_percent=_float_or_none(b.cpu_percent),
                     cpu_cores=b.cpu_cores, rss_bytes=b.rss_bytes, link=b.link)
        elif self.type == "error":
            d.update(code=b.code, name=b.name, text=b.text, sensor=b.sensor)
        elif self.type == "ack":
            d.update(command_sequence=b.command_sequence, kind=b.kind)
        elif self.type == "nack":
            d.update(command_sequence=b.command_sequence, kind=b.kind, code=b.code, text=b.text)
        elif self.type == "pong":
            d.update(command_sequence=b.command_sequence, host_send_ns=b.host_send_ns,
                     board_receive_ns=b.board_receive_ns)
        elif self.type == "frame_image":
            d["sensor"] = b.sensor
            name = hello.sensor_name(b.sensor) if hello else ""
            if name:
                d["sensor_name"] = name
            d.update(frame_sequence=b.frame_sequence, capture_ns=b.capture_ns)
            d.update(kind=b.kind, width=b.width, height=b.height, format=b.format, contact=b.contact,
                     mask_width=b.mask_width, mask_height=b.mask_height, mask=b.mask_rows(),
                     data=base64.b64encode(b.data).decode("ascii"))
        if self.type == "pong":
            d["round_trip_ns"] = (self.receive_ns - b.host_send_ns) - (self.send_ns - b.board_receive_ns)
        d["receive_ns"] = self.receive_ns
        if self.clock.valid:
            d["send_host_ns"] = self.to_host_ns(self.send_ns)
            if self.type in ("frame_prediction", "frame_image"):
                d["capture_host_ns"] = self.to_host_ns(b.capture_ns)
        return d
