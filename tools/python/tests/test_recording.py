"""Recordings made by the C++ side: the fixture recording (every message type and case) decoded
by this package gives the same JSON lines and link statistics as the C++ `tlvlink replay --json`;
a recording cut short ends cleanly; a recording written here reads back."""

import base64
import json
import os
import subprocess
import sys

import pytest

from conftest import REPO, tool
from tlvlink_stream import Client, RecordingReader, RecordingWriter
from tlvlink_stream.recording import RecordingError


def python_replay(path):
    client = Client(f"replay:{path}")
    out, hello = [], None
    for m in client.messages():
        if m.type == "hello":
            hello = m.body
        out.append(m.to_dict(hello))
    out.append({"type": "link_stats", "stats": client.stats.to_dict()})
    return out, client


def test_fixture_matches_the_cpp_replay_line_for_line(fixture_recording):
    cli = tool("TLVLINK_CLI")
    cpp = subprocess.run([cli, "replay", str(fixture_recording), "--json"], capture_output=True, text=True, check=True)
    cpp_lines = [json.loads(line) for line in cpp.stdout.splitlines() if line.startswith("{")]
    py_lines, _ = python_replay(fixture_recording)
    assert len(py_lines) == len(cpp_lines)
    for i, (p, c) in enumerate(zip(py_lines, cpp_lines)):
        assert p == c, f"line {i}: {p} != {c}"


def test_frame_images_match_the_cpp_replay_line_for_line(tmp_path, board_factory):
    """Protocol 1.2's FrameImages (mask rows, base64 JPEG) decode here as the C++ listener prints
    them: a live session with images recorded by `tlvlink listen`, replayed by both."""
    cli = tool("TLVLINK_CLI")
    link, rec = tmp_path / "tty", tmp_path / "images.tlvrec"
    board = board_factory(link, frames=60, rate=200.0, hold=1.0, images=5, wait_host=10)
    subprocess.run([cli, "listen", "--serial", str(link), "--json", "--count", "60", "--duration", "20",
                    "--record", str(rec)], capture_output=True, text=True, check=True, timeout=60)
    board.stop()
    cpp = subprocess.run([cli, "replay", str(rec), "--json"], capture_output=True, text=True, check=True)
    cpp_lines = [json.loads(line) for line in cpp.stdout.splitlines() if line.startswith("{")]
    py_lines, _ = python_replay(rec)
    assert len(py_lines) == len(cpp_lines)
    for i, (p, c) in enumerate(zip(py_lines, cpp_lines)):
        assert p == c, f"line {i}: {p} != {c}"
    images = [line for line in py_lines if line["type"] == "frame_image"]
    assert len(images) >= 10, len(images)
    for image in images:
        jpeg = base64.b64decode(image["data"])
        assert jpeg[:2] == b"\xff\xd8" and jpeg[-2:] == b"\xff\xd9"
        assert (image["width"], image["height"], image["mask_width"], image["mask_height"]) == (64, 48, 32, 24)
        assert len(image["mask"]) == 24 and sum(row.count("1") for row in image["mask"]) == 1


def test_fixture_contents(fixture_recording):
    lines, client = python_replay(fixture_recording)
    types = [d["type"] for d in lines[:-1]]
    assert types == ["hello", "frame_prediction", "frame_prediction", "grasp_prediction", "grasp_prediction", "stats",
                     "error", "pong", "nack", "frame_prediction", "frame_prediction", "hello", "frame_prediction"]
    s = client.stats
    assert (s.unknown_types, s.frames.version, s.board_restarts, s.delayed, s.connects, s.disconnects) == (1, 1, 1, 1, 2, 1)
    assert (s.sequence_gaps, s.frames_missing) == (2, 4)
    assert lines[1]["capture_host_ns"] == lines[1]["capture_ns"] - 5_000_000_000
    assert lines[4]["probability"] is None and lines[4]["reason"] == "missing_finger"
    assert lines[5]["drops"][2]["cause"] == 42
    assert lines[9]["frame_sequence"] == 77  # a newer minor version's message: unknown fields skipped
    kinds = [e.kind for e in client.take_events()]
    assert kinds == ["connected", "version_mismatch", "disconnected", "connected", "board_restarted", "end_of_recording"]


def test_cut_recording_ends_cleanly(tmp_path, stream_check):
    path = tmp_path / "cut.tlvrec"
    subprocess.run([stream_check, "record", str(path), "--cut"], check=True)
    lines, client = python_replay(path)
    assert len(lines) == 14
    assert "cut short" in client.take_events()[-1].text


def test_writer_reader_round_trip_and_bad_files(tmp_path):
    w = RecordingWriter(str(tmp_path / "r"))
    w.write(0, 42, b"\x01\x00\x02")
    w.write(2, 43, b"")
    w.close()
    records = list(RecordingReader(str(tmp_path / "r")))
    assert [(r.kind, r.time_ns, r.data) for r in records] == [(0, 42, b"\x01\x00\x02"), (2, 43, b"")]
    (tmp_path / "x").write_text("not a recording at all, honestly")
    with pytest.raises(RecordingError, match="not a tlvlink recording"):
        RecordingReader(str(tmp_path / "x"))


def _pong_recording(path, sent):
    """Link up, then a Pong to command #1 sent at t1 = 7 s; with `sent`, this client's own
    TimeSync #1 at that t1 is in the recording (kind 4), otherwise it was another host's."""
    from tlvlink_stream import wire
    from tlvlink_stream.commands import Command
    from tlvlink_stream.flatbuf import build_table
    from tlvlink_stream.recording import LINK_UP, RECEIVED, SENT_AUTO
    t1, offset = 7_000_000_000, 5_000_000_000
    w = RecordingWriter(str(path))
    w.write(LINK_UP, t1 - 1000, b"serial:/dev/ttyACM0 (test)")
    if sent:
        w.write(SENT_AUTO, t1, Command.ping().frame(1, t1))
    pong = build_table([(0, "I", 1), (1, "q", t1), (2, "q", t1 + offset + 50_000)])
    w.write(RECEIVED, t1 + 110_000, wire.encode_frame(wire.Header(type=0x08, sequence=0, send_ns=t1 + offset + 60_000), pong))
    w.close()


def test_a_pong_to_another_hosts_ping_does_not_set_the_clock(tmp_path):
    """Issue 31: only a Pong echoing a command this client sent (sequence and t1) is a clock
    exchange; another host's Pong set an offset off by the hosts' difference."""
    _pong_recording(tmp_path / "foreign", sent=False)
    client = Client(f"replay:{tmp_path / 'foreign'}")
    got = list(client.messages())
    assert [m.type for m in got] == ["pong"]  # not ours: delivered
    assert not client.clock().valid
    _pong_recording(tmp_path / "own", sent=True)
    client = Client(f"replay:{tmp_path / 'own'}")
    assert list(client.messages()) == []  # our own TimeSync's Pong: consumed
    assert client.clock().valid
