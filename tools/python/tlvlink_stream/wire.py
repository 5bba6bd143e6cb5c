"""The frame layer of the tlvlink stream (runtime/protocol/README.md): COBS framing with a 0x00
delimiter, the 24-byte little-endian header, CRC-32 (zlib's) over header and payload, and a
streaming Deframer that resynchronises after any damage and counts what it rejected."""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass, field
from typing import Callable, Iterable, List, Optional

MAGIC = b"TL"
VERSION_MAJOR = 1
VERSION_MINOR = 3  # 1: HeadInfo's cross-validated records; 2: FrameImage; 3: FramePrediction.gate
HEADER_SIZE = 24
CRC_SIZE = 4
MAX_FRAME_SIZE = 16384
MAX_PAYLOAD_SIZE = MAX_FRAME_SIZE - HEADER_SIZE - CRC_SIZE

FLAG_DELAYED = 0x0001
FLAGS_MUST_UNDERSTAND = 0xFF00

_HEADER = struct.Struct("<2sBBHHIIq")  # magic, major, minor, type, flags, sequence, payload_length, send_ns


def cobs_max_encoded_size(n: int) -> int:
    return n + n // 254 + 1


MAX_WIRE_FRAME_SIZE = cobs_max_encoded_size(MAX_FRAME_SIZE) + 1


def crc32(data: bytes, crc: int = 0) -> int:
    return zlib.crc32(data, crc) & 0xFFFFFFFF


def cobs_encode(data: bytes) -> bytes:
    """COBS without the trailing delimiter (a full run at the very end gets no extra code byte)."""
    out = bytearray(b"\x00")
    code_pos, code = 0, 1
    for i, b in enumerate(data):
        if code == 0xFF:  # the previous run is full and more data follows
            out[code_pos] = 0xFF
            code_pos, code = len(out), 1
            out.append(0)
        if b == 0:
            out[code_pos] = code
            code_pos, code = len(out), 1
            out.append(0)
        else:
            out.append(b)
            code += 1
    out[code_pos] = code
    return bytes(out)


class CobsError(ValueError):
    pass


def cobs_decode(data: bytes) -> bytes:
    out = bytearray()
    i, n = 0, len(data)
    while i < n:
        code = data[i]
        i += 1
        if code == 0:
            raise CobsError(f"zero byte inside a frame at {i - 1}")
        run = code - 1
        if run > n - i:
            raise CobsError(f"code byte at {i - 1} runs {run - (n - i)} bytes past the end of the frame")
        chunk = data[i:i + run]
        if 0 in chunk:
            raise CobsError(f"zero byte inside a frame after {i}")
        out += chunk
        i += run
        if code != 0xFF and i < n:
            out.append(0)
    return bytes(out)


@dataclass
class Header:
    version_major: int = VERSION_MAJOR
    version_minor: int = VERSION_MINOR
    type: int = 0
    flags: int = 0
    sequence: int = 0
    payload_length: int = 0
    send_ns: int = 0

    def pack(self) -> bytes:
        return _HEADER.pack(MAGIC, self.version_major, self.version_minor, self.type, self.flags,
                            self.sequence & 0xFFFFFFFF, self.payload_length, self.send_ns)

    @staticmethod
    def unpack(data: bytes) -> "Header":
        _, major, minor, type_, flags, seq, length, send_ns = _HEADER.unpack_from(data)
        return Header(major, minor, type_, flags, seq, length, send_ns)


def encode_frame(header: Header, payload: bytes) -> bytes:
    """COBS(header || payload || CRC-32) followed by the 0x00 delimiter."""
    if len(payload) > MAX_PAYLOAD_SIZE:
        raise ValueError(f"payload of {len(payload)} bytes exceeds the protocol's {MAX_PAYLOAD_SIZE}")
    header.payload_length = len(payload)
    body = header.pack() + payload
    return cobs_encode(body + struct.pack("<I", crc32(body))) + b"\x00"


# Verdicts, in the order they are checked (the same names as the C++ FrameVerdict).
OK, OVERSIZED, COBS, TRUNCATED, CRC, BAD_MAGIC, VERSION, LENGTH, FLAGS = (
    "ok", "oversized", "cobs", "truncated", "crc", "magic", "version", "length", "flags")


def check_frame(frame: bytes):
    """Validates one COBS-decoded frame; returns (verdict, header or None, payload or None)."""
    if len(frame) < 4 + CRC_SIZE:
        return TRUNCATED, None, None
    body = len(frame) - CRC_SIZE
    magic = frame[0:2] == MAGIC
    readable = magic and body >= HEADER_SIZE
    if crc32(frame[:body]) != struct.unpack_from("<I", frame, body)[0]:
        if readable and Header.unpack(frame).payload_length > body - HEADER_SIZE:
            return TRUNCATED, None, None
        return CRC, None, None
    if not magic:
        return BAD_MAGIC, None, None
    if frame[2] != VERSION_MAJOR:
        return VERSION, Header(version_major=frame[2], version_minor=frame[3]), None
    if len(frame) < HEADER_SIZE + CRC_SIZE:
        return TRUNCATED, None, None
    h = Header.unpack(frame)
    if h.payload_length != body - HEADER_SIZE or h.payload_length > MAX_PAYLOAD_SIZE:
        return LENGTH, h, None
    if h.flags & FLAGS_MUST_UNDERSTAND:
        return FLAGS, h, None
    return OK, h, bytes(frame[HEADER_SIZE:body])


@dataclass
class DeframerCounters:
    bytes: int = 0
    frames: int = 0
    oversized: int = 0
    cobs: int = 0
    truncated: int = 0
    crc: int = 0
    magic: int = 0
    version: int = 0
    length: int = 0
    flags: int = 0
    discarded_bytes: int = 0

    def rejected(self) -> int:
        return (self.oversized + self.cobs + self.truncated + self.crc + self.magic + self.version
                + self.length + self.flags)


@dataclass
class ReceivedFrame:
    verdict: str
    header: Optional[Header]
    payload: Optional[bytes]
    wire: bytes


class Deframer:
    """Bytes in (any chunking), one ReceivedFrame per delimited segment out."""

    def __init__(self) -> None:
        self._segment = bytearray()
        self._overflow = False
        self.counters = DeframerCounters()

    def reset(self) -> None:
        """Forgets a partly received segment (after a reconnect); not counted."""
        self._segment.clear()
        self._overflow = False

    def feed(self, data: bytes) -> List[ReceivedFrame]:
        c = self.counters
        c.bytes += len(data)
        out: List[ReceivedFrame] = []
        start = 0
        while start < len(data):
            zero = data.find(b"\x00", start)
            stop = len(data) if zero < 0 else zero
            self._append(data[start:stop])
            if zero < 0:
                break
            start = zero + 1
            if self._segment or self._overflow:
                out.append(self._finish())
        return out

    def _append(self, chunk: bytes) -> None:
        if not chunk:
            return
        c = self.counters
        if self._overflow or len(chunk) > MAX_WIRE_FRAME_SIZE - 1 - len(self._segment):
            if not self._overflow:
                c.discarded_bytes += len(self._segment)
            self._overflow = True
            self._segment.clear()
            c.discarded_bytes += len(chunk)
            return
        self._segment += chunk

    def _finish(self) -> ReceivedFrame:
        c = self.counters
        wire = bytes(self._segment)
        self._segment.clear()
        if self._overflow:
            self._overflow = False
            c.oversized += 1
            return ReceivedFrame(OVERSIZED, None, None, b"")
        try:
            frame = cobs_decode(wire)
        except CobsError:
            verdict, header, payload = COBS, None, None
        else:
            if len(frame) > MAX_FRAME_SIZE:
                verdict, header, payload = OVERSIZED, None, None
            else:
                verdict, header, payload = check_frame(frame)
        if verdict == OK:
            c.frames += 1
        else:
            setattr(c, verdict, getattr(c, verdict) + 1)
            c.discarded_bytes += len(wire)
        return ReceivedFrame(verdict, header, payload, wire)
