"""Recording files (tools/listen/README.md "Recording format"), as `tlvlink listen --record`
writes them: a 32-byte header, then records of (host time, kind, bytes). Kinds: 0 bytes
received, 1 link up (text), 2 link down (text), 3 commands the user sent, 4 the client's own
commands (Info, TimeSync), whose replies a client consumes."""

from __future__ import annotations

import struct
import time
from dataclasses import dataclass
from typing import BinaryIO, Iterator

MAGIC = b"TLVLREC\n"
VERSION = 1
HEADER_SIZE = 32
RECORD_HEADER = struct.Struct("<qIB3x")
MAX_RECORD = 1 << 20
RECEIVED, LINK_UP, LINK_DOWN, SENT, SENT_AUTO = range(5)


class RecordingError(ValueError):
    pass


@dataclass
class Record:
    kind: int
    time_ns: int  # host CLOCK_MONOTONIC
    data: bytes


class RecordingReader:
    def __init__(self, path: str) -> None:
        self._file: BinaryIO = open(path, "rb")
        header = self._file.read(HEADER_SIZE)
        if len(header) < HEADER_SIZE or header[:8] != MAGIC:
            self._file.close()
            raise RecordingError(f"{path} is not a tlvlink recording (no TLVLREC header)")
        version, size = struct.unpack_from("<HH", header, 8)
        if version != VERSION:
            self._file.close()
            raise RecordingError(f"{path}: recording format version {version}; this package reads version {VERSION}")
        self.start_wall_ns, self.start_monotonic_ns = struct.unpack_from("<qq", header, 16)
        self._file.seek(size)
        self.truncated = False

    def __iter__(self) -> Iterator[Record]:
        while True:
            head = self._file.read(RECORD_HEADER.size)
            if not head:
                return
            if len(head) < RECORD_HEADER.size:
                self.truncated = True
                return
            t, n, kind = RECORD_HEADER.unpack(head)
            if n > MAX_RECORD:
                raise RecordingError(f"record of {n} bytes (at most {MAX_RECORD})")
            data = self._file.read(n)
            if len(data) < n:
                self.truncated = True
                return
            yield Record(kind, t, data)

    def close(self) -> None:
        self._file.close()


class RecordingWriter:
    def __init__(self, path: str) -> None:
        self._file: BinaryIO = open(path, "wb")
        self._file.write(MAGIC + struct.pack("<HHIqq", VERSION, HEADER_SIZE, 0, time.time_ns(), time.monotonic_ns()))

    def write(self, kind: int, time_ns: int, data: bytes) -> None:
        self._file.write(RECORD_HEADER.pack(time_ns, len(data), kind) + data)

    def close(self) -> None:
        self._file.close()
