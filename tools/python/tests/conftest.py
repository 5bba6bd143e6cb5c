"""Shared pieces of the Python client's tests. ctest (tests/listen/CMakeLists.txt) runs them with
Debian's /usr/bin/python3 and sets:
  TLVLINK_STREAM_CHECK  the C++ board/recording program (tools/listen/bench/stream_check.cc)
  TLVLINK_CLI           the tlvlink binary, when built with the host tools (C++ replay to compare)
  TLVLINK_SCHEMA_HASH   the schema hash CMake computed from stream.fbs (hex)
A test that needs one of them and does not have it is skipped, saying so."""

import os
import pathlib
import signal
import subprocess
import sys
import time

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "tools" / "python"))


def tool(name):
    path = os.environ.get(name)
    if not path or not os.path.exists(path):
        pytest.skip(f"{name} not set: run through ctest (tests/listen) or set it to the built program")
    return path


@pytest.fixture
def stream_check():
    return tool("TLVLINK_STREAM_CHECK")


@pytest.fixture
def fixture_recording(tmp_path, stream_check):
    path = tmp_path / "fixture.tlvrec"
    subprocess.run([stream_check, "record", str(path)], check=True)
    return path


class Board:
    """A C++ board process (tlvlink_stream_check board) on a pty, killed by its pid at the end."""

    def __init__(self, stream_check, link, frames=100, rate=200.0, hold=10.0, boot_id=0x5EED, embedding=False,
                 images=0, wait_host=0.0):
        args = [stream_check, "board", "--link", f"pty:{link}", "--frames", str(frames), "--rate", str(rate),
                "--hold", str(hold), "--boot-id", str(boot_id)]
        if embedding:
            args.append("--embedding")
        if images:
            args += ["--images", str(images)]  # a FrameImage after every images-th prediction
        if wait_host:
            # Posts nothing until a host has synced its clock: a client that opens the pty late
            # (a loaded machine) still sees every prediction from the first.
            args += ["--wait-host", str(wait_host)]
        self.link = str(link)
        self.process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        for _ in range(300):
            if os.path.exists(self.link):
                break
            time.sleep(0.01)

    def stop(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
        out, _ = self.process.communicate(timeout=20)
        return out


@pytest.fixture
def board_factory(stream_check):
    boards = []

    def make(link, **kwargs):
        b = Board(stream_check, link, **kwargs)
        boards.append(b)
        return b

    yield make
    for b in boards:
        if b.process.poll() is None:
            b.process.kill()
            b.process.wait()


def fixture_value(n, k):
    """The C++ stream_fixture's value(n, k), as float32."""
    import struct
    v = ((n * 7919 + k * 104729) % 1000) / 1000.0
    return struct.unpack("<f", struct.pack("<f", v))[0]


def f32(x):
    import struct
    return struct.unpack("<f", struct.pack("<f", x))[0]


def fixture_prediction_intact(m):
    """Every field of a FramePrediction the C++ fixture_prediction(n) made."""
    n = m.frame_sequence
    if m.sensor != n % 2 or m.contact != (n % 3 == 0):
        return False
    if m.stage_ns != [n * 10 + k for k in range(5)]:
        return False
    if len(m.heads) != 2 or m.heads[0].head != 0 or m.heads[1].head != 1:
        return False
    if m.heads[0].probabilities != [fixture_value(n, k) for k in range(4)]:
        return False
    if m.heads[1].probabilities != [fixture_value(n, 10 + k) for k in range(2)]:
        return False
    if m.embedding and m.embedding != [f32(fixture_value(n, 100 + k) - 0.5) for k in range(32)]:
        return False
    return True
