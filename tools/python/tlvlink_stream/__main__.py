"""python3 -m tlvlink_stream listen|replay: what `tlvlink listen` / `tlvlink replay` print, from
the Python client (the same JSON lines; text lines in short form)."""

from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import time

from . import Client, parse_command
from .transports import LinkUnavailable


def _text(m, hello) -> str:
    d = m.to_dict(hello)
    if m.type == "frame_prediction":
        heads = " ".join(f"{h.get('name', 'head%d' % h['head'])}={h.get('top_label', '?')}({h.get('top_probability', 0):.2f})"
                         for h in d["heads"])
        return f"frame  s{m.sensor} #{m.frame_sequence} {'contact' if m.contact else 'no-contact'}  {heads}"
    keys = {k: v for k, v in d.items() if k not in ("type", "sequence", "flags", "delayed", "send_ns", "receive_ns")}
    return f"{m.type:<6} {json.dumps(keys)}"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python3 -m tlvlink_stream", description=__doc__)
    sub = p.add_subparsers(dest="mode", required=True)
    listen = sub.add_parser("listen", help="receive the board's prediction stream")
    g = listen.add_mutually_exclusive_group(required=True)
    g.add_argument("--serial", help="serial device: a UART, /dev/ttyACM0, a pty link")
    g.add_argument("--usb", nargs="?", const="", help="USB bulk: VID:PID[,serial=S] (default 1d6b:0104)")
    g.add_argument("--source", help="a source string (serial:..., usb:...)")
    listen.add_argument("--baud", type=int, default=0)
    listen.add_argument("--record", help="also record what arrives into FILE")
    listen.add_argument("-c", "--command", dest="commands", action="append", default=[],
                        help="send once the board said hello")
    replay = sub.add_parser("replay", help="replay a recording")
    replay.add_argument("file")
    replay.add_argument("--realtime", action="store_true")
    for q in (listen, replay):
        q.add_argument("--json", action="store_true", help="JSON lines (the C++ listener's keys)")
        q.add_argument("--count", type=int, default=0, help="stop after this many frame predictions")
        q.add_argument("--duration", type=float, default=None, help="stop after this many seconds")
    a = p.parse_args(argv)

    if a.mode == "replay":
        client = Client("replay:" + a.file, realtime=a.realtime)
    else:
        source = a.source or (f"serial:{a.serial}" + (f",baud={a.baud}" if a.baud else "") if a.serial else
                              ("usb" if not a.usb else "usb:" + a.usb))
        client = Client(source, record=a.record)
    commands = [parse_command(c) for c in getattr(a, "commands", [])]
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    end = time.monotonic() + a.duration if a.duration is not None else None
    predictions, hello = 0, None
    with client:
        while not stop.is_set() and (end is None or time.monotonic() < end):
            m = client.next(0.1)
            for e in client.take_events():
                print(f"# {e.kind}: {e.text}", file=sys.stderr)
            if m is None:
                if client.ended:
                    break
                continue
            if m.type == "hello":
                hello = m.body
                for c in commands:
                    try:
                        print(f"# sent #{client.send(c)} {c.kind}", file=sys.stderr)
                    except LinkUnavailable as e:
                        print(f"# command {c.kind}: {e}", file=sys.stderr)
                commands = []
            print(json.dumps(m.to_dict(hello)) if a.json else _text(m, hello), flush=True)
            if m.type == "frame_prediction":
                predictions += 1
                if a.count and predictions >= a.count:
                    break
        if a.json:
            print(json.dumps({"type": "link_stats", "stats": client.stats.to_dict()}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
