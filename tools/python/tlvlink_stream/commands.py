"""Host -> board commands: building and encoding them, and parsing them as people type them
("start", "closed 3", "set threads=2"; the same syntax as `tlvlink listen --command`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from . import schema, wire
from .flatbuf import build_table

ALL_SENSORS = 255


@dataclass
class Command:
    kind: str                     # schema.ENUMS["CommandKind"] name
    sensor: int = ALL_SENSORS     # start, stop, rezero
    grasp_id: int = 0             # grasp_closed, grasp_lifting
    event_ns: int = 0             # grasp marks: when, on the board clock (0: on receipt)
    key: str = ""                 # set_config
    value: str = ""
    clock_offset_ns: int = 0      # time_sync: the host's estimate, if any
    clock_uncertainty_ns: int = 0

    @staticmethod
    def start(sensor: int = ALL_SENSORS) -> "Command":
        return Command("start", sensor=sensor)

    @staticmethod
    def stop(sensor: int = ALL_SENSORS) -> "Command":
        return Command("stop", sensor=sensor)

    @staticmethod
    def grasp_closed(grasp_id: int, event_ns: int = 0) -> "Command":
        return Command("grasp_closed", grasp_id=grasp_id, event_ns=event_ns)

    @staticmethod
    def grasp_lifting(grasp_id: int, event_ns: int = 0) -> "Command":
        return Command("grasp_lifting", grasp_id=grasp_id, event_ns=event_ns)

    @staticmethod
    def rezero(sensor: int = ALL_SENSORS) -> "Command":
        return Command("rezero", sensor=sensor)

    @staticmethod
    def set_config(key: str, value: str) -> "Command":
        return Command("set_config", key=key, value=value)

    @staticmethod
    def info() -> "Command":
        return Command("info")

    @staticmethod
    def ping() -> "Command":
        return Command("ping")

    def payload(self) -> bytes:
        kind = schema.ENUMS["CommandKind"].index(self.kind)
        s = lambda name: schema.slot("Command", name)  # noqa: E731
        return build_table([
            (s("kind"), "B", kind),
            (s("sensor"), "B", self.sensor if self.sensor != ALL_SENSORS else None),
            (s("grasp_id"), "I", self.grasp_id or None),
            (s("event_ns"), "q", self.event_ns or None),
            (s("key"), "string", self.key or None),
            (s("value"), "string", self.value or None),
            (s("clock_offset_ns"), "q", self.clock_offset_ns or None),
            (s("clock_uncertainty_ns"), "q", self.clock_uncertainty_ns or None),
        ])

    def frame(self, sequence: int, send_ns: int) -> bytes:
        """The whole wire frame (COBS, delimiter included)."""
        header = wire.Header(type=schema.MESSAGE_TYPE_NUMBERS["command"], sequence=sequence, send_ns=send_ns)
        return wire.encode_frame(header, self.payload())


_ALIASES = {"closed": "grasp_closed", "lifting": "grasp_lifting", "set": "set_config", "sync": "time_sync",
            "timesync": "time_sync"}


def parse_command(text: str) -> Command:
    """start [SENSOR] | stop [SENSOR] | closed ID | lifting ID | rezero [SENSOR] | set KEY=VALUE |
    info | ping | time_sync. ValueError naming what is wrong."""
    parts = text.strip().split(None, 1)
    verb = _ALIASES.get(parts[0], parts[0]) if parts else ""
    arg: Optional[str] = parts[1].strip() if len(parts) > 1 else None
    if verb not in schema.ENUMS["CommandKind"][1:]:
        raise ValueError(f"unknown command '{text.strip()}' (start [SENSOR], stop [SENSOR], closed ID, lifting ID, "
                         f"rezero [SENSOR], set KEY=VALUE, info, ping, time_sync)")
    c = Command(verb)
    if verb in ("start", "stop", "rezero"):
        if arg is not None:
            if not arg.isdigit() or int(arg) > 254:
                raise ValueError(f"command: sensor '{arg}' is not a number up to 254")
            c.sensor = int(arg)
    elif verb in ("grasp_closed", "grasp_lifting"):
        if arg is None:
            raise ValueError(f"command '{verb}' needs a grasp id")
        if not arg.isdigit() or int(arg) > 0xFFFFFFFF:
            raise ValueError(f"command: grasp id '{arg}' is not a number up to 4294967295")
        c.grasp_id = int(arg)
    elif verb == "set_config":
        if arg is None or "=" not in arg or arg.startswith("="):
            raise ValueError(f"command 'set' needs KEY=VALUE, got '{arg or ''}'")
        key, value = arg.split("=", 1)
        c.key, c.value = key.strip(), value.strip()
    elif arg is not None:
        raise ValueError(f"command '{verb}' takes no argument")
    return c
