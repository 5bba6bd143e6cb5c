"""Just enough flatbuffers for the tlvlink stream, in pure Python: reading tables, scalars,
structs, strings and vectors with every offset bounds-checked (a payload is untrusted input),
and building the one table a host writes (Command). Debian has python3-flatbuffers, but it would
mean generated code (which this repository never commits) or hand-written accessors on top of it
anyway, and it checks no bounds; the wire format is small enough to read directly.

Format (flatbuffers.dev, "Internals"): little-endian; the buffer starts with a u32 offset to the
root table; a table starts with an i32 `soffset` (vtable = table - soffset); a vtable is u16 its
size, u16 the table's size, then one u16 per field: the field's offset in the table, 0 = absent
(the default applies). Offsets to strings, vectors and sub-tables are u32, relative to where
they are stored; a string or vector is a u32 length followed by its elements (strings with a
trailing 0)."""

from __future__ import annotations

import struct
from typing import List, Optional


class DecodeError(ValueError):
    """The payload is not a valid table of the expected shape."""


class Table:
    __slots__ = ("buf", "pos", "_vt", "_vt_len")

    def __init__(self, buf: bytes, pos: int) -> None:
        self.buf = buf
        self.pos = pos
        _need(buf, pos, 4)
        vt = pos - struct.unpack_from("<i", buf, pos)[0]
        _need(buf, vt, 4)
        vt_len = struct.unpack_from("<H", buf, vt)[0]
        if vt_len < 4 or vt_len % 2:
            raise DecodeError(f"vtable of {vt_len} bytes")
        _need(buf, vt, vt_len)
        self._vt, self._vt_len = vt, vt_len

    @staticmethod
    def root(buf: bytes) -> "Table":
        _need(buf, 0, 4)
        return Table(buf, struct.unpack_from("<I", buf, 0)[0])

    def _field(self, slot: int) -> int:
        """Absolute position of field `slot`, or 0 when absent (fields unknown to an older writer)."""
        at = 4 + 2 * slot
        if at >= self._vt_len:
            return 0
        off = struct.unpack_from("<H", self.buf, self._vt + at)[0]
        return self.pos + off if off else 0

    def scalar(self, slot: int, fmt: str, default=0):
        p = self._field(slot)
        if not p:
            return default
        _need(self.buf, p, struct.calcsize(fmt))
        return struct.unpack_from("<" + fmt, self.buf, p)[0]

    def struct_at(self, slot: int, size: int) -> Optional[int]:
        """Position of an inline struct field, or None."""
        p = self._field(slot)
        if not p:
            return None
        _need(self.buf, p, size)
        return p

    def _indirect(self, slot: int) -> Optional[int]:
        p = self._field(slot)
        if not p:
            return None
        _need(self.buf, p, 4)
        return p + struct.unpack_from("<I", self.buf, p)[0]

    def string(self, slot: int) -> str:
        p = self._indirect(slot)
        return "" if p is None else _string_at(self.buf, p)

    def table(self, slot: int) -> Optional["Table"]:
        p = self._indirect(slot)
        return None if p is None else Table(self.buf, p)

    def _vector(self, slot: int, element_size: int):
        p = self._indirect(slot)
        if p is None:
            return None, 0
        _need(self.buf, p, 4)
        n = struct.unpack_from("<I", self.buf, p)[0]
        _need(self.buf, p + 4, n * element_size)
        return p + 4, n

    def scalars(self, slot: int, fmt: str) -> List:
        start, n = self._vector(slot, struct.calcsize(fmt))
        return [] if start is None else list(struct.unpack_from(f"<{n}{fmt}", self.buf, start))

    def bytes_vector(self, slot: int) -> bytes:
        """A [ubyte] vector as bytes (an image, a mask), b"" when absent."""
        start, n = self._vector(slot, 1)
        return b"" if start is None else bytes(self.buf[start:start + n])

    def strings(self, slot: int) -> List[str]:
        start, n = self._vector(slot, 4)
        if start is None:
            return []
        return [_string_at(self.buf, start + 4 * i + struct.unpack_from("<I", self.buf, start + 4 * i)[0])
                for i in range(n)]

    def tables(self, slot: int) -> List["Table"]:
        start, n = self._vector(slot, 4)
        if start is None:
            return []
        return [Table(self.buf, start + 4 * i + struct.unpack_from("<I", self.buf, start + 4 * i)[0])
                for i in range(n)]

    def structs(self, slot: int, size: int) -> List[int]:
        """Positions of the elements of a vector of structs."""
        start, n = self._vector(slot, size)
        return [] if start is None else [start + size * i for i in range(n)]


def _need(buf: bytes, pos: int, n: int) -> None:
    if pos < 0 or n < 0 or pos + n > len(buf):
        raise DecodeError(f"{n} bytes at {pos} are outside the {len(buf)}-byte payload")


def _string_at(buf: bytes, p: int) -> str:
    _need(buf, p, 4)
    n = struct.unpack_from("<I", buf, p)[0]
    _need(buf, p + 4, n + 1)
    # Invalid UTF-8 is not a reason to drop a message (README §7): U+FFFD, as the C++ client.
    return bytes(buf[p + 4:p + 4 + n]).decode("utf-8", "replace")


def build_table(fields: List[tuple]) -> bytes:
    """One root table. `fields`: (slot, kind, value) with kind a struct format ("B", "I", "q", ...)
    for scalars or "string"; None values are left out (the reader's default applies).

    Layout: root offset, vtable, table (soffset then the scalars, each aligned to its size), then
    the strings; every offset points forward, as flatbuffers readers require."""
    present = [(slot, kind, value) for slot, kind, value in fields if value is not None]
    n_slots = (max(slot for slot, _, _ in present) + 1) if present else 0
    vt_len = 4 + 2 * n_slots
    table_pos = (4 + vt_len + 7) & ~7
    # Table body: soffset (4 bytes) then fields; strings hold a u32 offset in the table.
    offsets = {}
    body = bytearray(4)
    for slot, kind, value in present:
        size = 4 if kind == "string" else struct.calcsize(kind)
        while (table_pos + len(body)) % size:
            body.append(0)
        offsets[slot] = len(body)
        body += bytes(size)
    table_len = len(body)
    buf = bytearray(table_pos) + body
    while len(buf) % 4:
        buf.append(0)
    for slot, kind, value in present:
        at = table_pos + offsets[slot]
        if kind == "string":
            data = value.encode("utf-8")
            target = len(buf)
            buf += struct.pack("<I", len(data)) + data + b"\x00"
            while len(buf) % 4:
                buf.append(0)
            struct.pack_into("<I", buf, at, target - at)
        else:
            struct.pack_into("<" + kind, buf, at, value)
    struct.pack_into("<I", buf, 0, table_pos)
    struct.pack_into("<HH", buf, 4, vt_len, table_len)
    for slot, _, _ in present:
        struct.pack_into("<H", buf, 4 + 4 + 2 * slot, offsets[slot])
    struct.pack_into("<i", buf, table_pos, table_pos - 4)
    while len(buf) % 8:
        buf.append(0)
    return bytes(buf)
