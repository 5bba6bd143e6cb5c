"""Commands as people type them, and the Command tables this package builds (read back with its
own reader here; the C++ board decodes them in test_live.py)."""

import pytest

from tlvlink_stream import Command, parse_command, schema, wire
from tlvlink_stream.flatbuf import Table


def test_parse_every_command():
    assert parse_command("start") == Command("start")
    assert parse_command(" stop 1 ").sensor == 1
    assert parse_command("closed 42") == Command("grasp_closed", grasp_id=42)
    assert parse_command("lifting 7").kind == "grasp_lifting"
    assert parse_command("set heads = material,grasp") == Command("set_config", key="heads", value="material,grasp")
    for verb in ("info", "ping", "time_sync", "rezero"):
        assert parse_command(verb).kind == verb


@pytest.mark.parametrize("text,says", [("launch", "unknown command 'launch'"), ("closed", "needs a grasp id"),
                                       ("closed x", "grasp id 'x'"), ("start 255", "sensor '255'"),
                                       ("set threads", "KEY=VALUE"), ("ping now", "takes no argument")])
def test_mistakes_are_named(text, says):
    with pytest.raises(ValueError, match=says):
        parse_command(text)


def test_command_table_reads_back():
    c = Command("set_config", sensor=1, grasp_id=9, event_ns=-5, key="heads", value="grasp",
                clock_offset_ns=-42, clock_uncertainty_ns=7)
    payload = c.payload()
    assert len(payload) % 8 == 0
    t = Table.root(payload)
    s = lambda n: schema.slot("Command", n)  # noqa: E731
    assert t.scalar(s("kind"), "B") == schema.ENUMS["CommandKind"].index("set_config")
    assert (t.scalar(s("sensor"), "B", 255), t.scalar(s("grasp_id"), "I"), t.scalar(s("event_ns"), "q")) == (1, 9, -5)
    assert (t.string(s("key")), t.string(s("value"))) == ("heads", "grasp")
    assert (t.scalar(s("clock_offset_ns"), "q"), t.scalar(s("clock_uncertainty_ns"), "q")) == (-42, 7)
    assert Table.root(Command("ping").payload()).scalar(s("sensor"), "B", 255) == 255  # absent: default


def test_command_frame():
    f = Command("ping").frame(sequence=7, send_ns=123)
    verdict, header, payload = wire.check_frame(wire.cobs_decode(f[:-1]))
    assert (verdict, header.type, header.sequence, header.send_ns) == (wire.OK, 0x80, 7, 123)
