"""The Python client of the prediction stream: the same behaviour as the C++ listen::Client
(tools/listen/include/tlvlink/listen/client.h), so both print the same for the same bytes.

    from tlvlink_stream import Client, Command
    with Client("serial:/dev/ttyACM0") as client:          # or "usb", "replay:run.tlvrec"
        client.send(Command.start())                        # once connected
        for msg in client.messages():
            if msg.type == "frame_prediction":
                print(msg.sensor, msg.heads[0].probabilities, client.board_to_host_ns(msg.capture_ns))

It reconnects by itself, asks for a Hello if none came within 300 ms of connecting, keeps the
board's clock offset with TimeSync once a second (their replies are consumed here), and counts
what the link lost (stats)."""

from __future__ import annotations

import collections
import math
import threading
import time
from dataclasses import dataclass, field
from typing import Callable, Deque, Dict, Iterator, List, Optional, Tuple

from . import schema, wire
from .clock import ClockEstimate, ClockSync
from .commands import Command
from .flatbuf import DecodeError
from .messages import ClockSnapshot, Hello, Message, decode
from .recording import LINK_DOWN, LINK_UP, RECEIVED, SENT, SENT_AUTO, RecordingReader, RecordingWriter
from .transports import LinkLost, LinkUnavailable, open_source

INFO_AFTER_NS = 300_000_000
BURST_SYNCS = 3
BURST_GAP_NS = 50_000_000
REMEMBERED_OWN_COMMANDS = 64


class LatencyWindow:
    CAPACITY = 8192

    def __init__(self) -> None:
        self._samples: List[int] = []
        self._next = 0
        self.count = 0
        self.max = 0

    def add(self, ns: int) -> None:
        if len(self._samples) < self.CAPACITY:
            self._samples.append(ns)
        else:
            self._samples[self._next] = ns
        self._next = (self._next + 1) % self.CAPACITY
        self.count += 1
        self.max = max(self.max, ns)

    def percentile(self, p: float) -> int:
        """Nearest rank over the samples in the window (0 when empty)."""
        if not self._samples:
            return 0
        s = sorted(self._samples)
        rank = math.ceil(p / 100.0 * len(s))
        return s[min(len(s) - 1, rank - 1 if rank > 0 else 0)]

    def to_dict(self) -> Dict[str, int]:
        return {"count": self.count, "p50_ns": self.percentile(50), "p99_ns": self.percentile(99), "max_ns": self.max}


@dataclass
class LinkStats:
    frames: wire.DeframerCounters = field(default_factory=wire.DeframerCounters)
    messages: int = 0
    unknown_types: int = 0
    undecodable: int = 0
    sequence_gaps: int = 0
    frames_missing: int = 0
    sequence_resets: int = 0
    board_restarts: int = 0
    delayed: int = 0
    connects: int = 0
    disconnects: int = 0
    link_up: bool = False
    link_latency: LatencyWindow = field(default_factory=LatencyWindow)
    capture_latency: LatencyWindow = field(default_factory=LatencyWindow)
    round_trip: LatencyWindow = field(default_factory=LatencyWindow)
    clock: ClockEstimate = field(default_factory=ClockEstimate)

    def to_dict(self) -> dict:
        """The keys of the C++ `tlvlink listen --json` link_stats line."""
        f = self.frames
        return {
            "bytes": f.bytes, "frames": f.frames,
            "rejected": {"oversized": f.oversized, "cobs": f.cobs, "truncated": f.truncated, "crc": f.crc,
                         "magic": f.magic, "version": f.version, "length": f.length, "flags": f.flags},
            "discarded_bytes": f.discarded_bytes, "messages": self.messages, "unknown_types": self.unknown_types,
            "undecodable": self.undecodable, "sequence_gaps": self.sequence_gaps,
            "frames_missing": self.frames_missing, "sequence_resets": self.sequence_resets,
            "board_restarts": self.board_restarts, "delayed": self.delayed, "connects": self.connects,
            "disconnects": self.disconnects, "link_up": self.link_up,
            "link_latency": self.link_latency.to_dict(), "capture_latency": self.capture_latency.to_dict(),
            "round_trip": self.round_trip.to_dict(),
            "clock": {"valid": self.clock.valid, "offset_ns": self.clock.offset_ns,
                      "uncertainty_ns": self.clock.uncertainty_ns},
        }


@dataclass
class LinkEvent:
    kind: str  # connected, disconnected, version_mismatch, board_restarted, end_of_recording
    text: str
    time_ns: int


class Client:
    def __init__(self, source: str, *, reconnect: bool = True, reconnect_min_s: float = 0.1,
                 reconnect_max_s: float = 1.0, time_sync_s: float = 1.0, request_info: bool = True,
                 record: Optional[str] = None, realtime: bool = False) -> None:
        self.source = source
        self._reconnect = reconnect
        self._backoff_min = int(reconnect_min_s * 1e9)
        self._backoff_max = int(reconnect_max_s * 1e9)
        self._backoff = self._backoff_min
        self._sync_period = int(time_sync_s * 1e9)
        self._request_info = request_info
        self._realtime = realtime
        self._lock = threading.Lock()
        self._deframer = wire.Deframer()
        self._sent_deframer = wire.Deframer()
        self._ready: Deque[Message] = collections.deque()
        self._events: List[LinkEvent] = []
        self._own: Deque[int] = collections.deque(maxlen=REMEMBERED_OWN_COMMANDS)
        # (sequence, header send time) of every command sent, own or the user's: a Pong counts
        # for the clock only when it echoes one (another host's Pong carries its clock's t1).
        self._sent: Deque[Tuple[int, int]] = collections.deque(maxlen=REMEMBERED_OWN_COMMANDS)
        self._out_user = bytearray()
        self._out_auto = bytearray()
        self._next_sequence = 0
        self._clock = ClockSync()
        self.stats = LinkStats()
        self.hello: Optional[Message] = None
        self._boot_id: Optional[int] = None
        self._last_sequence: Optional[int] = None
        self._version_reported = False
        self._next_open = 0
        self._next_sync = 0
        self._info_due = 0
        self._burst = 0
        self._down_reason = ""
        self._ended = False
        self._recorder: Optional[RecordingWriter] = None
        self._replay: Optional[Iterator] = None
        self._replay_reader: Optional[RecordingReader] = None
        self._pending = None
        self._replay_offset: Optional[int] = None
        self._link = None
        if source.startswith("replay:"):
            self._replay_reader = RecordingReader(source[len("replay:"):])
            self._replay = iter(self._replay_reader)
        else:
            self._link = open_source(source)
        if record:
            if self._replay is not None:
                raise ValueError("record with a replay: copy the file instead")
            self._recorder = RecordingWriter(record)

    # ---------------------------------------------------------------- public API

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self._link is not None:
            self._link.close()
        if self._recorder is not None:
            self._recorder.close()
            self._recorder = None
        if self._replay_reader is not None:
            self._replay_reader.close()

    @property
    def ended(self) -> bool:
        return self._ended and not self._ready

    def next(self, timeout: Optional[float] = None) -> Optional[Message]:
        """The next message, waiting up to `timeout` seconds (None: until one comes or a recording
        ends); None on timeout or at the end of a recording."""
        while not self._ready and not self._ended:
            deadline = time.monotonic_ns() + (int(timeout * 1e9) if timeout is not None else 3_600_000_000_000)
            if self._replay is not None:
                self._pump_replay(deadline)
            else:
                self._pump_live(deadline)
            if timeout is not None:
                break
        return self._ready.popleft() if self._ready else None

    def messages(self, timeout: Optional[float] = None) -> Iterator[Message]:
        """Every message until the recording ends (live: forever, or until `timeout` seconds
        pass without one)."""
        while True:
            m = self.next(timeout)
            if m is None:
                if self._ended or timeout is not None:
                    return
                continue
            yield m

    def run(self, on_message: Callable[[Message], None], on_event: Optional[Callable[[LinkEvent], None]] = None,
            duration: Optional[float] = None, stop: Optional[threading.Event] = None) -> None:
        end = time.monotonic() + duration if duration is not None else math.inf
        while not (stop is not None and stop.is_set()) and time.monotonic() < end:
            m = self.next(min(0.1, max(0.0, end - time.monotonic())))
            for e in self.take_events():
                if on_event:
                    on_event(e)
            if m is not None:
                on_message(m)
            if self.ended:
                return

    def take_events(self) -> List[LinkEvent]:
        with self._lock:
            events, self._events = self._events, []
        return events

    def send(self, command: Command) -> int:
        """Sends a command (any thread); returns its sequence number (the Ack/Nack/Pong names it)."""
        if self._link is None:
            raise RuntimeError("a recording cannot take commands")
        with self._lock:
            if not self.stats.link_up:
                raise LinkUnavailable(f"{self.source} is not connected" + (f": {self._down_reason}" if self._down_reason else ""))
            sequence = self._next_sequence
            self._next_sequence = (self._next_sequence + 1) & 0xFFFFFFFF
            send_ns = time.monotonic_ns()
            self._out_user += command.frame(sequence, send_ns)
            self._sent.append((sequence, send_ns))
        return sequence

    def clock(self) -> ClockEstimate:
        with self._lock:
            return self._clock.estimate(time.monotonic_ns())

    def board_to_host_ns(self, board_ns: int) -> int:
        with self._lock:
            return self._clock.board_to_host(board_ns)

    def host_to_board_ns(self, host_ns: int) -> int:
        with self._lock:
            return self._clock.host_to_board(host_ns)

    @property
    def hello_body(self) -> Optional[Hello]:
        return self.hello.body if self.hello is not None else None

    # ---------------------------------------------------------------- frames

    def _event(self, kind: str, text: str, t: int) -> None:
        with self._lock:
            self._events.append(LinkEvent(kind, text, t))

    def _record(self, kind: int, t: int, data: bytes) -> None:
        if self._recorder is not None:
            self._recorder.write(kind, t, data)

    def _track_sequence(self, sequence: int) -> None:
        if self._last_sequence is not None:
            gap = (sequence - (self._last_sequence + 1)) & 0xFFFFFFFF
            if gap != 0 and gap < 0x80000000:
                self.stats.sequence_gaps += 1
                self.stats.frames_missing += gap
            elif gap != 0:
                self.stats.sequence_resets += 1
        self._last_sequence = sequence

    def _on_bytes(self, data: bytes, t: int) -> None:
        for f in self._deframer.feed(data):
            self._on_frame(f, t)
        self.stats.frames = self._deframer.counters

    def _on_frame(self, f: wire.ReceivedFrame, t: int) -> None:
        if f.verdict == wire.VERSION:
            if not self._version_reported:
                self._version_reported = True
                self._event("version_mismatch",
                            f"the board speaks stream protocol {f.header.version_major}.{f.header.version_minor}; "
                            f"this client speaks {wire.VERSION_MAJOR}.{wire.VERSION_MINOR}: its frames are refused "
                            f"(update the client or the board)", t)
            return
        if f.verdict != wire.OK:
            return
        h = f.header
        type_name = schema.MESSAGE_TYPES.get(h.type)
        is_hello = type_name == "hello"
        s = self.stats
        if not is_hello:
            self._track_sequence(h.sequence)
        if type_name is None or type_name == "command":
            s.unknown_types += 1
            return
        try:
            body = decode(type_name, f.payload)
        except DecodeError:
            s.undecodable += 1
            return
        s.messages += 1
        if h.flags & wire.FLAG_DELAYED:
            s.delayed += 1
        m = Message(type_name, h.sequence, h.flags, h.send_ns, t, body)
        deliver = True
        if is_hello:
            if self._boot_id is not None and body.boot_id != self._boot_id:
                s.board_restarts += 1
                self._clock.reset()
                self._last_sequence = None
                self._event("board_restarted", "the board restarted (new boot id)", t)
            self._boot_id = body.boot_id
            self.hello = m
            self._info_due = 0
            self._track_sequence(h.sequence)
        if type_name == "pong":
            if (body.command_sequence, body.host_send_ns) in self._sent and \
                    self._clock.add(body.host_send_ns, body.board_receive_ns, h.send_ns, t):
                s.round_trip.add((t - body.host_send_ns) - (h.send_ns - body.board_receive_ns))
            deliver = body.command_sequence not in self._own
        elif type_name in ("ack", "nack"):
            deliver = body.command_sequence not in self._own
        s.clock = self._clock.estimate(t)
        m.clock = ClockSnapshot(s.clock.valid, s.clock.offset_ns, s.clock.uncertainty_ns)
        if s.clock.valid:
            s.link_latency.add(t - self._clock.board_to_host(h.send_ns))
            if type_name == "frame_prediction":
                s.capture_latency.add(t - self._clock.board_to_host(body.capture_ns))
        if deliver:
            self._ready.append(m)

    # ---------------------------------------------------------------- live link

    def _queue_own(self, command: Command) -> None:
        with self._lock:
            sequence = self._next_sequence
            self._next_sequence = (self._next_sequence + 1) & 0xFFFFFFFF
            send_ns = time.monotonic_ns()
            self._out_auto += command.frame(sequence, send_ns)
            self._own.append(sequence)
            self._sent.append((sequence, send_ns))

    def _connected(self) -> None:
        now = time.monotonic_ns()
        self._deframer.reset()
        self._backoff = self._backoff_min
        self._version_reported = False
        with self._lock:
            self.stats.connects += 1
            self.stats.link_up = True
            self._out_user.clear()
            self._out_auto.clear()
        self._record(LINK_UP, now, self._link.name.encode())
        self._event("connected", self._link.name, now)
        self._info_due = now + INFO_AFTER_NS if self._request_info else 0
        self._next_sync = now
        self._burst = BURST_SYNCS if self._sync_period > 0 else 0

    def _disconnected(self, why: str) -> None:
        now = time.monotonic_ns()
        self._link.close()
        with self._lock:
            self.stats.disconnects += 1
            self.stats.link_up = False
        self._record(LINK_DOWN, now, why.encode())
        self._event("disconnected", why, now)
        self._down_reason = why
        self._next_open = now + self._backoff_min

    def _write_pending(self) -> None:
        with self._lock:
            user = bool(self._out_user)
            out = self._out_user if user else self._out_auto
            data = bytes(out)
            out.clear()
        if data:
            self._link.write(data)
            self._record(SENT if user else SENT_AUTO, time.monotonic_ns(), data)

    def _pump_live(self, deadline: int) -> None:
        while not self._ready:
            now = time.monotonic_ns()
            if now >= deadline:
                return
            if not self._link.is_open:
                if now < self._next_open:
                    time.sleep((min(deadline, self._next_open) - now) / 1e9)
                    continue
                try:
                    self._link.open()
                except LinkUnavailable as e:
                    if not self._reconnect:
                        raise
                    if self._down_reason != str(e):  # each new reason once
                        self._down_reason = str(e)
                        self._event("disconnected", self._down_reason, now)
                    self._next_open = now + self._backoff
                    self._backoff = min(2 * self._backoff, self._backoff_max)
                    continue
                self._connected()
            if self._info_due and now >= self._info_due:
                self._info_due = 0
                self._queue_own(Command.info())
            if self._sync_period > 0 and now >= self._next_sync:
                sync = Command("time_sync")
                with self._lock:
                    e = self._clock.estimate(now)
                if e.valid:
                    sync.clock_offset_ns, sync.clock_uncertainty_ns = e.offset_ns, max(1, e.uncertainty_ns)
                self._queue_own(sync)
                self._next_sync = now + (BURST_GAP_NS if self._burst > 0 else self._sync_period)
                self._burst = max(0, self._burst - 1)
            try:
                self._write_pending()
                self._write_pending()
                until = deadline
                if self._sync_period > 0:
                    until = min(until, self._next_sync)
                if self._info_due:
                    until = min(until, self._info_due)
                data = self._link.read(min(max(until - time.monotonic_ns(), 0), 1_000_000_000) / 1e9)
            except LinkLost as e:
                if not self._reconnect:
                    raise
                self._disconnected(str(e))
                continue
            if data:
                t = time.monotonic_ns()
                self._record(RECEIVED, t, data)
                self._on_bytes(data, t)

    # ---------------------------------------------------------------- recordings

    def _pump_replay(self, deadline: int) -> None:
        while not self._ready and not self._ended:
            if self._pending is None:
                try:
                    self._pending = next(self._replay)
                except StopIteration:
                    self._ended = True
                    cut = self._replay_reader.truncated
                    self._event("end_of_recording",
                                "end of recording (its last record was cut short)" if cut else "end of recording",
                                time.monotonic_ns())
                    return
            r = self._pending
            if self._realtime:
                now = time.monotonic_ns()
                if self._replay_offset is None:
                    self._replay_offset = now - r.time_ns
                due = r.time_ns + self._replay_offset
                if due > now:
                    if now >= deadline:
                        return
                    time.sleep((min(due, deadline) - now) / 1e9)
                    continue
            if r.kind == RECEIVED:
                self._on_bytes(r.data, r.time_ns)
            elif r.kind == LINK_UP:
                self._deframer.reset()
                self._version_reported = False
                self.stats.connects += 1
                self.stats.link_up = True
                self._event("connected", r.data.decode("utf-8", "replace"), r.time_ns)
            elif r.kind == LINK_DOWN:
                self.stats.disconnects += 1
                self.stats.link_up = False
                self._event("disconnected", r.data.decode("utf-8", "replace"), r.time_ns)
            elif r.kind in (SENT_AUTO, SENT):
                for f in self._sent_deframer.feed(r.data):
                    if f.verdict == wire.OK:
                        if r.kind == SENT_AUTO:
                            self._own.append(f.header.sequence)
                        self._sent.append((f.header.sequence, f.header.send_ns))
            self._pending = None
            if not self._realtime and time.monotonic_ns() >= deadline:
                return
