"""The stream's conformance cases (runtime/protocol/conformance/cases.json, README section 16)
through this package's receiving side: every delimited segment gets the outcome the file names,
as the C++ client does (tests/listen/conformance_test.cc runs the same file)."""

import json

import pytest

from conftest import REPO
from tlvlink_stream import schema, wire
from tlvlink_stream.flatbuf import DecodeError
from tlvlink_stream.messages import Message, decode

CASES = json.loads((REPO / "runtime" / "protocol" / "conformance" / "cases.json").read_text())["cases"]


def case_bytes(case):
    return b"".join(bytes.fromhex(p["hex"]) * p.get("repeat", 1) for p in case["wire"])


def outcome(f):
    """What a host makes of one segment (client.py _on_frame): a verdict, or ok:TYPE,
    unknown_type, undecodable; with the decoded body for ok frames."""
    if f.verdict != wire.OK:
        return f.verdict, None
    type_name = schema.MESSAGE_TYPES.get(f.header.type)
    if type_name is None or type_name == "command":
        return "unknown_type", None
    try:
        body = decode(type_name, f.payload)
    except DecodeError:
        return "undecodable", None
    return f"ok:{type_name}", Message(type_name, f.header.sequence, f.header.flags, f.header.send_ns, 0, body)


def test_there_are_cases():
    assert len(CASES) >= 25


@pytest.mark.parametrize("case", CASES, ids=[c["name"] for c in CASES])
def test_case(case):
    got = []
    for f in wire.Deframer().feed(case_bytes(case)):
        result, message = outcome(f)
        got.append(result)
        for key, value in case.get("fields", {}).items():
            assert message is not None and message.to_dict()[key] == value, case["note"]
    assert got == case["expect"], case["note"]
