"""The package's idea of the schema against stream.fbs itself: every table's fields in slot
order, every enum's values, and the schema hash (recomputed here, by CMake, and in the package)."""

import os
import re

from tlvlink_stream import schema
from conftest import REPO

FBS = (REPO / "runtime" / "protocol" / "schema" / "stream.fbs").read_text()


def _blocks(kind):
    text = re.sub(r"//[^\n]*", "", FBS)
    return {m.group(1): m.group(2) for m in re.finditer(kind + r"\s+(\w+)\s*(?::\s*\w+\s*)?\{([^}]*)\}", text)}


def snake(name):
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def test_tables_and_structs_match_the_schema():
    tables = {n: [f.split(":")[0].strip() for f in b.split(";") if f.strip()] for n, b in _blocks("table").items()}
    assert tables == schema.TABLES
    structs = {n: [f.split(":")[0].strip() for f in b.split(";") if f.strip()] for n, b in _blocks("struct").items()}
    assert structs == schema.STRUCTS


def test_enums_match_the_schema():
    for name, body in _blocks("enum").items():
        values = {}
        for item in body.split(","):
            key, _, value = item.partition("=")
            values[int(value)] = snake(key.strip())
        assert [values[i] for i in range(len(values))] == schema.ENUMS[name], name


def test_schema_hash():
    computed = schema.schema_hash_of(FBS)
    assert computed == schema.SCHEMA_HASH, (
        f"stream.fbs changed (hash {computed:016x}): update tlvlink_stream/schema.py (SCHEMA_HASH and any new fields)")
    if os.environ.get("TLVLINK_SCHEMA_HASH"):
        assert int(os.environ["TLVLINK_SCHEMA_HASH"], 16) == computed, "CMake and Python disagree on the hash"


def test_comments_do_not_change_the_hash():
    assert schema.schema_hash_of(FBS + "\n// a new comment\n") == schema.SCHEMA_HASH
    assert schema.schema_hash_of(FBS.replace("table Ack {", "table Ack  {\n")) == schema.SCHEMA_HASH
    assert schema.schema_hash_of(FBS.replace("kind: CommandKind;", "kind: ubyte;", 1)) != schema.SCHEMA_HASH
