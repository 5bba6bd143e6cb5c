"""The frame layer: COBS against the published examples, CRC-32 against its check value, frames
as the specification lays them out, and the deframer under garbage, truncation, bit flips,
oversized segments and forged lengths/CRCs (seeded: TLVLINK_TEST_SEED replays)."""

import os
import random
import struct

import pytest

from tlvlink_stream import wire

SEED = int(os.environ.get("TLVLINK_TEST_SEED", "1"))


def test_crc_check_value():
    assert wire.crc32(b"123456789") == 0xCBF43926


@pytest.mark.parametrize("raw,encoded", [
    (b"\x00", b"\x01\x01"),
    (b"\x00\x00", b"\x01\x01\x01"),
    (b"\x11\x22\x00\x33", b"\x03\x11\x22\x02\x33"),
    (b"\x11\x00\x00\x00", b"\x02\x11\x01\x01\x01"),
    (bytes(range(1, 255)), b"\xff" + bytes(range(1, 255))),
    (bytes(range(1, 256)), b"\xff" + bytes(range(1, 255)) + b"\x02\xff"),
])
def test_cobs_examples(raw, encoded):
    assert wire.cobs_encode(raw) == encoded
    assert wire.cobs_decode(encoded) == raw


def test_cobs_random_round_trips():
    rng = random.Random(SEED)
    for _ in range(500):
        data = bytes(rng.choice([0, 0, rng.randrange(256)]) for _ in range(rng.randrange(800)))
        enc = wire.cobs_encode(data)
        assert 0 not in enc and len(enc) <= wire.cobs_max_encoded_size(len(data))
        assert wire.cobs_decode(enc) == data


def test_frame_layout():
    h = wire.Header(type=0x02, flags=1, sequence=0x01020304, send_ns=0x1122334455667788)
    f = wire.cobs_decode(wire.encode_frame(h, b"\xaa\x00\xbb")[:-1])
    assert f[:24] == bytes([0x54, 0x4C, 1, wire.VERSION_MINOR, 2, 0, 1, 0, 4, 3, 2, 1, 3, 0, 0, 0,
                            0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11])
    assert f[24:27] == b"\xaa\x00\xbb"
    assert struct.unpack("<I", f[27:])[0] == wire.crc32(f[:27])


def frame(seq, size=40):
    return wire.encode_frame(wire.Header(type=0x04, sequence=seq), bytes((seq * 131 + i * 7) & 0xFF for i in range(size)))


def test_resync_after_garbage_and_every_damage():
    rng = random.Random(SEED)
    d = wire.Deframer()
    got = []
    for s in range(50):
        garbage = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 300))) + b"\x00"
        got += d.feed(garbage)
        got += d.feed(frame(s))
    ok = [f.header.sequence for f in got if f.verdict == wire.OK]
    assert ok == list(range(50))
    assert d.counters.rejected() > 0


def test_truncated_oversized_forged():
    d = wire.Deframer()
    cut = frame(0, 100)
    cut = cut[:30] + cut[60:]  # bytes lost in the middle, delimiter kept
    got = d.feed(cut) + d.feed(frame(1))
    got += d.feed(b"\x55" * (wire.MAX_WIRE_FRAME_SIZE + 10)) + d.feed(frame(2)) + d.feed(frame(3))
    forged = bytearray(wire.cobs_decode(frame(4)[:-1]))
    struct.pack_into("<I", forged, 12, 10_000)  # a lying length with a valid CRC
    struct.pack_into("<I", forged, len(forged) - 4, wire.crc32(bytes(forged[:-4])))
    got += d.feed(wire.cobs_encode(bytes(forged)) + b"\x00") + d.feed(frame(5))
    ok = [f.header.sequence for f in got if f.verdict == wire.OK]
    assert ok == [1, 3, 5]
    c = d.counters
    assert (c.truncated + c.crc + c.cobs, c.oversized, c.length) == (1, 1, 1)


def test_bit_flips_never_yield_a_corrupted_frame():
    rng = random.Random(SEED)
    sizes = {s: rng.randrange(200) for s in range(1000)}
    stream = bytearray(b"".join(frame(s, sizes[s]) for s in range(1000)))
    for i in range(len(stream)):
        if rng.random() < 0.002:
            stream[i] ^= 1 << rng.randrange(8)
    got = [f for f in wire.Deframer().feed(bytes(stream)) if f.verdict == wire.OK]
    for f in got:
        s = f.header.sequence
        assert f.payload == bytes((s * 131 + i * 7) & 0xFF for i in range(sizes[s]))
    assert 500 < len(got) < 1000


def test_version_and_flags():
    h = wire.Header(version_major=2, version_minor=5)
    verdict, header, _ = wire.check_frame(wire.cobs_decode(wire.encode_frame(h, b"x")[:-1]))
    assert (verdict, header.version_major, header.version_minor) == (wire.VERSION, 2, 5)
    assert wire.check_frame(wire.cobs_decode(wire.encode_frame(wire.Header(flags=0x0100), b"x")[:-1]))[0] == wire.FLAGS
    assert wire.check_frame(wire.cobs_decode(wire.encode_frame(wire.Header(version_minor=9), b"x")[:-1]))[0] == wire.OK
