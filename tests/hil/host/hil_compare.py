#!/usr/bin/env python3
"""Compares every prediction of the emulated board's HIL run with the host build's on the same
frames, and counts per run what was computed and what was delivered (tests/hil/README.md).

Inputs: the host reference's JSON lines (tlvlinkd replaying the recording, `embedding = true`),
the guest's JSON lines as they arrived over virtio-serial (split into runs by the guest's
{"type":"hil"} markers), the USB host side's recordings per run (decoded with the repository's
Python client, tools/python), and the rig's report (boot and first-prediction times).

Each guest prediction is matched to the host frame whose embedding is nearest (frames are told
apart by far more than the tolerance; the script prints the margin), then:
  JSON lines: int8 tensor identical to the host's, embedding and probabilities within tolerance;
  stream:     embedding and probabilities within tolerance;
  both:       frames in the order they were fed (per daemon start).
Exit 1 on any mismatch (printed with the frame and the values) or a loss beyond its bound.
Standard library only (+ tools/python on sys.path).
"""
import argparse
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "tools", "python"))
from tlvlink_stream import Client  # noqa: E402

# x86-64 (SSE/AVX microkernels) vs aarch64 (NEON) float: the embedding is an fp32
# FullyConnected over 256 dequantized int8 values (identical on both: compared exactly on the
# JSON-lines path); summation order and FMA change only the last bits (256 terms x 2^-24
# relative ~ 1.5e-5 worst case). 1e-4 of the largest magnitude is the cross stage's parity
# tolerance (tests/parity) and still ~1,000x below the distance between two frames' embeddings
# (printed: frames are identified by their nearest embedding).
EMBEDDING_REL_TOL = 1e-4
# Heads: linear probes + softmax on that embedding, fp32 on both sides: the same few-ulp
# argument; 1e-4 absolute is far above it and far below any change of a reported label.
PROB_ABS_TOL = 1e-4
# A press head (runtime/heads README "Press heads"; tools/score names them LABEL_press) reads the
# contact so far, not the frame: stateful like gating and smoothing, which both runs turn off so
# that each prediction depends on its frame only. Its answers depend on which frames each run
# saw before (restarts, reloads, losses), so they are not compared frame by frame.
PRESS_SUFFIX = "_press"


def load_jsonl(path):
    out = []
    with open(path, "rb") as f:
        for n, raw in enumerate(f, 1):
            line = raw.decode("utf-8", "replace").strip()
            if not line:
                continue
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError as e:
                sys.exit(f"hil_compare: {path}:{n}: not JSON ({e}): {line[:120]}")
    return out


def probs_of(heads, names=None):
    """{head name: [p...]} from a JSON line's 'heads' (the one JSON-lines form: tlvlinkd's
    jsonl: output as `tlvlink listen --json` prints) or stream HeadOutputs (+ Hello names)."""
    if heads and isinstance(heads[0], dict):
        return {h["name"]: h["probabilities"] for h in heads}
    return {names[h.head]: list(h.probabilities) for h in heads}


def is_summary(line):
    """The daemon's last stats line of a run (its summary)."""
    return line.get("type") == "stats" and line.get("final") is True


class Reference:
    """The host's predictions, one per distinct frame (repeats of a frame give identical ones)."""

    def __init__(self, lines):
        summary = [l for l in lines if is_summary(l)]
        if not summary:
            sys.exit("hil_compare: the host reference has no summary line (did it stop cleanly?)")
        self.drops = summary[-1]["daemon"]["drops"]  # the replay may skip a record (e.g. its last); what
        # counts is that every distinct frame the feeder fed has a reference (checked in main)
        self.frames = []  # distinct frames in recorded order: (first seq, int8, embedding, probs)
        seen = {}
        for l in lines:
            if l.get("type") != "frame_prediction":
                continue
            key = tuple(l["int8"])
            if key in seen:
                continue
            seen[key] = len(self.frames)
            self.frames.append((l["frame_sequence"], l["int8"], l["embedding"], probs_of(l["heads"])))
        self.scale = max(abs(v) for f in self.frames for v in f[2])
        self.tol = EMBEDDING_REL_TOL * self.scale
        # The smallest distance between two distinct frames' embeddings: the identification margin.
        self.margin = math.inf
        for i in range(len(self.frames)):
            for j in range(i):
                a, b = self.frames[i][2], self.frames[j][2]
                self.margin = min(self.margin, max(abs(x - y) for x, y in zip(a, b)))

    def nearest(self, embedding):
        best, best_d = -1, math.inf
        for i, f in enumerate(self.frames):
            d = max(abs(x - y) for x, y in zip(f[2], embedding))
            if d < best_d:
                best, best_d = i, d
        return best, best_d


class Check:
    """Compares predictions with the reference; keeps the figures and the failures."""

    def __init__(self, ref):
        self.ref = ref
        self.failures = []
        self.max_emb = {"jsonl": 0.0, "stream": 0.0}
        self.max_prob = {"jsonl": 0.0, "stream": 0.0}
        self.compared = {"jsonl": 0, "stream": 0}
        self.int8_identical = 0
        self.frames_seen = set()

    def fail(self, text):
        if len(self.failures) < 20:
            print("MISMATCH " + text)
        self.failures.append(text)

    def one(self, where, what, embedding, probs, int8=None):
        """Returns the distinct frame index it matched (-1: none)."""
        i, d = self.ref.nearest(embedding)
        seq, ref_int8, ref_emb, ref_probs = self.ref.frames[i]
        self.compared[where] += 1
        if int8 is not None:
            if list(int8) == ref_int8:
                self.int8_identical += 1
            else:
                diff = [(k, a, b) for k, (a, b) in enumerate(zip(int8, ref_int8)) if a != b]
                self.fail(f"{what}: int8 tensor differs from host frame {i} (seq {seq}) at {len(diff)} "
                          f"of {len(ref_int8)} values, e.g. (index, board, host) {diff[:6]}")
        if d > self.ref.tol:
            self.fail(f"{what}: embedding matches no host frame: nearest is frame {i} (seq {seq}) at "
                      f"max |diff| {d:.3g} > tolerance {self.ref.tol:.3g}")
            return -1
        self.max_emb[where] = max(self.max_emb[where], d)
        for name, ps in ref_probs.items():
            if name.endswith(PRESS_SUFFIX):
                continue
            got = probs.get(name)
            if got is None or len(got) != len(ps):
                self.fail(f"{what}: head {name} missing or of another size (frame {i})")
                continue
            dp = max(abs(a - b) for a, b in zip(got, ps))
            self.max_prob[where] = max(self.max_prob[where], dp)
            if dp > PROB_ABS_TOL:
                self.fail(f"{what}: head {name} probabilities {got} vs host {ps} (frame {i}, seq {seq}): "
                          f"max |diff| {dp:.3g} > {PROB_ABS_TOL}")
        self.frames_seen.add(i)
        return i

    def ordered(self, what, indices):
        last = -1
        for n, i in enumerate(indices):
            if i >= 0 and i < last:
                self.fail(f"{what}: prediction {n} is of frame {i}, after frame {last}: not the fed order")
            last = max(last, i)


def split_runs(lines):
    """{run: {"lines": [...], "marks": [...]}} from the guest's JSON lines and its markers."""
    runs, current = {}, None
    for l in lines:
        if l.get("type") == "hil":
            if l["event"] == "begin":
                current = runs.setdefault(l["scenario"], {"lines": [], "marks": [], "instances": []})
            if current is not None:
                current["marks"].append(l)
                if l["event"] in ("begin", "daemon_start") and (l["event"] == "daemon_start" or
                                                                 l["scenario"] != "daemon_kill"):
                    current["instances"].append([])
            if l["event"] == "end":
                current = None
        elif current is not None:
            current["lines"].append(l)
            if current["instances"]:
                current["instances"][-1].append(l)
    return runs


def decode_relay(path):
    """Frame predictions of one recording: (receive uptime s, boot id, message), + link stats."""
    out, boot, names = [], None, []
    last_stats = None
    client = Client("replay:" + path, reconnect=False)
    for m in client.messages():
        if m.type == "hello":
            boot, names = m.body.boot_id, [h.name for h in m.body.heads]
        elif m.type == "frame_prediction":
            out.append((m.receive_ns / 1e9, boot, m.body, names))
        elif m.type == "stats":
            last_stats = m.body
    stats = client.stats.to_dict()
    client.close()
    # A reader started mid-stream may get predictions before the Hello it asked for: they belong
    # to the next Hello's daemon start.
    for k in range(len(out) - 1, -1, -1):
        if out[k][1] is None:
            later = next((o[1] for o in out[k + 1:] if o[1] is not None), 0)
            out[k] = (out[k][0], later, out[k][2], out[k][3] or next((o[3] for o in out if o[3]), []))
    return out, stats, last_stats


def instance_counts(lines):
    """Computed predictions of one daemon start: its summary's `encoded` when it stopped, else the
    larger of its last stats' `encoded` and its frame lines (a SIGKILLed daemon writes no summary)."""
    frames = [l for l in lines if l.get("type") == "frame_prediction"]
    summaries = [l for l in lines if is_summary(l)]
    stats = [l for l in lines if l.get("type") == "stats" and "daemon" in l]
    if summaries:
        return summaries[-1]["daemon"]["encoded"], frames, True
    return max([s["daemon"]["encoded"] for s in stats] + [len(frames)]), frames, False


def camera_counts(lines):
    """Camera outages of one daemon start (its stats lines' run report: the summary's, else the
    last): outages begun, ended by a reopen, reopen attempts failed, seconds without a camera."""
    reports = [l for l in lines if l.get("type") == "stats" and "camera" in l.get("daemon", {})]
    if not reports:
        return 0, 0, 0, 0.0
    c = reports[-1]["daemon"]["camera"]
    return (sum(c["disconnects"]), sum(c["reconnects"]), sum(c["reopen_failures"]),
            sum(c["outage_s"]))


def rig_figures(path):
    text = open(path, errors="replace").read() if path and os.path.exists(path) else ""
    boot = re.search(r"boot to init ([0-9.]+)s \(guest kernel uptime ([0-9.]+)s\)", text)
    first = re.search(r"first prediction at the USB host at guest uptime ([0-9.]+) s", text)
    return (float(boot.group(1)), float(boot.group(2))) if boot else None, float(first.group(1)) if first else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--host", required=True)
    ap.add_argument("--guest-jsonl", required=True)
    ap.add_argument("--relay", required=True, help="directory of RUN/*.tlvrec")
    ap.add_argument("--rig-log")
    ap.add_argument("--label", default="board")
    a = ap.parse_args()

    ref = Reference(load_jsonl(a.host))
    print(f"host reference: {len(ref.frames)} distinct frames; embedding tolerance {ref.tol:.3g} "
          f"({EMBEDDING_REL_TOL:g} x max |e| {ref.scale:.3g}); smallest distance between two frames' "
          f"embeddings {ref.margin:.3g} ({ref.margin / ref.tol:.0f}x the tolerance); probabilities {PROB_ABS_TOL:g}")
    if ref.margin <= 2 * ref.tol:
        sys.exit("hil_compare: two distinct frames are closer than twice the tolerance: frames cannot be told apart")
    fed = None  # the feeder's count of distinct frames in the recording
    for root, _, files in os.walk(a.relay):
        for f in files:
            if f == "feeder.log":
                m = re.search(r"\((\d+) distinct\)", open(os.path.join(root, f)).read())
                fed = int(m.group(1)) if m else fed
    if fed is None:
        sys.exit(f"hil_compare: no feeder.log under {a.relay}: cannot tell how many distinct frames were fed")
    if len(ref.frames) != fed:
        sys.exit(f"hil_compare: the host reference has {len(ref.frames)} distinct frames, the recording {fed} "
                 f"(host drops {ref.drops}): run the reference again")
    check = Check(ref)
    runs = split_runs(load_jsonl(a.guest_jsonl))
    if "clean" not in runs:
        check.fail("no clean run in the guest's JSON lines")
    table = []
    for name, run in runs.items():
        run_dir = os.path.join(a.relay, name)
        recs = sorted(f for f in os.listdir(run_dir) if f.endswith(".tlvrec")) if os.path.isdir(run_dir) else []
        if not recs:
            check.fail(f"{name}: no recording from the USB host side in {run_dir}")
        # JSON lines (virtio-serial): every one compared, int8 included.
        computed, bound_kill, lines_total, instances_done = 0, 0, 0, []
        cam = [0, 0, 0, 0.0]  # camera lost, back, reopen attempts failed, seconds without it
        for k, inst in enumerate(run["instances"]):
            c, frames, stopped = instance_counts(inst)
            cam = [x + y for x, y in zip(cam, camera_counts(inst))]
            computed += c
            lines_total += len(frames)
            instances_done.append(stopped)
            idx = [check.one("jsonl", f"{name} daemon start {k} jsonl seq {f['frame_sequence']}",
                             f["embedding"], probs_of(f["heads"]), f["int8"]) for f in frames]
            check.ordered(f"{name} daemon start {k} (JSON lines)", idx)
            if not stopped and frames:  # SIGKILLed: what it computed in its last second may be lost
                last = frames[-1]["capture_ns"]
                bound_kill += sum(1 for f in frames if f["capture_ns"] >= last - 1_000_000_000) + (c - len(frames))
        # The stream (USB): every prediction compared; delivered = distinct (boot, sensor, frame
        # sequence, capture time).
        delivered, rejected, by_boot, last_uptime = set(), 0, {}, []
        for r in recs:
            preds, stats, _ = decode_relay(os.path.join(run_dir, r))
            rejected += sum(stats["rejected"].values())
            for t, boot, p, names in preds:
                i = check.one("stream", f"{name} {r} boot {boot:x} frame_sequence {p.frame_sequence}",
                              p.embedding, probs_of(p.heads, names))
                by_boot.setdefault(boot, []).append(i)
                # frame_sequence restarts at 0 when the camera is reopened (runtime/capture): the
                # capture time tells a post-reload frame from an earlier one with the same number;
                # a resent frame (replug) has the same three.
                delivered.add((boot, p.sensor, p.frame_sequence, p.capture_ns))
                last_uptime.append(t)
        for boot, idx in by_boot.items():
            check.ordered(f"{name} boot {boot:x} (stream)", idx)
        marks = {m["event"]: m for m in run["marks"]}
        events = os.path.join(run_dir, "events.jsonl")  # the guest's markers, fault times included
        if os.path.exists(events):
            marks.update({m["event"]: m for m in load_jsonl(events)})
        lost = computed - len(delivered)
        after = None
        if name == "clean" or name == "vivid_reload":
            bound, why = 0, "the link was not touched"
        elif name == "reader_restart":
            bound, why = 1, "one bulk transfer read by the killed reader"
            after = marks.get("reader_killed")
        elif name == "replug":
            bound, why = 1, "the transfer in flight at the unbind"
            after = marks.get("unplug")
        elif name == "garbage":
            bursts = marks.get("garbage_end", {}).get("bursts", 0)
            # One frame per burst into the stream (the burst is one write(): it lands inside or
            # between frames, the deframer resyncs at the next delimiter). One more was lost once
            # in the 7 runs on record, on a loaded host (4 for 3 bursts, 2026-12-05): not isolated; the bound
            # admits it and says so rather than failing the board stage at random.
            bound, why = bursts + 1, f"one frame per garbage burst ({bursts}) + 1 seen once, cause not isolated"
            after = marks.get("garbage_end")
            if rejected == 0:
                check.fail("garbage: the host decoder rejected nothing: the garbage did not reach it")
        elif name == "daemon_kill":
            bound, why = bound_kill, "the killed daemon's last second of predictions"
            after = marks.get("killed")
            if len(by_boot) < 2:
                check.fail(f"daemon_kill: predictions from {len(by_boot)} daemon start(s) reached the host, expected 2")
        else:
            bound, why = 0, "?"
        if name == "vivid_reload":
            fed_after = [i for idx in by_boot.values() for i in idx if i >= 50]
            if not fed_after:
                check.fail("vivid_reload: no prediction of a frame fed after the reload reached the host")
            if cam[0] < 1 or cam[1] != cam[0]:
                check.fail(f"vivid_reload: camera lost {cam[0]} time(s), back {cam[1]}: expected every "
                           "outage (at least the unplug) to end with a reopen")
        if after is not None and not any(t > after["uptime_s"] for t in last_uptime):
            check.fail(f"{name}: no prediction reached the host after the fault (uptime {after['uptime_s']})")
        if lost > bound:
            check.fail(f"{name}: computed {computed}, delivered {len(delivered)}, lost {lost} > bound {bound} ({why})")
        if lost < 0:
            check.fail(f"{name}: delivered {len(delivered)} > computed {computed}: predictions counted twice?")
        table.append((name, computed, lines_total, len(delivered), lost, bound, why, rejected, len(by_boot), cam))

    print(f"\nHIL {a.label}: every prediction against the host build (x86-64) on the same frames")
    print(f"| path | predictions compared | int8 tensors identical | max embedding diff | max probability diff |")
    print(f"|---|---|---|---|---|")
    print(f"| JSON lines (virtio-serial) | {check.compared['jsonl']} | {check.int8_identical} / {check.compared['jsonl']} "
          f"| {check.max_emb['jsonl']:.3g} | {check.max_prob['jsonl']:.3g} |")
    print(f"| stream (USB; CDC-ACM in 'garbage') | {check.compared['stream']} | (not sent) | "
          f"{check.max_emb['stream']:.3g} | {check.max_prob['stream']:.3g} |")
    print(f"distinct frames predicted: {len(check.frames_seen)} of {len(ref.frames)}")
    print(f"\n| run | computed | JSON lines | delivered (USB) | lost | bound | bound because | rejected by the host decoder | daemon starts seen | camera lost / back (failed reopens, s without) |")
    print(f"|---|---|---|---|---|---|---|---|---|---|")
    for name, c, jl, d, lost, bound, why, rej, boots, cam in table:
        print(f"| {name} | {c} | {jl} | {d} | {lost} | {bound} | {why} | {rej} | {boots} | "
              f"{cam[0]} / {cam[1]} ({cam[2]}, {cam[3]:.2f} s) |")
    for name, c, jl, d, lost, bound, why, rej, boots, cam in table:
        print(f"note: hil {name}: computed {c}, delivered {d}, lost {lost} (bound {bound}); camera lost {cam[0]}, back {cam[1]}")
    boot, first = rig_figures(a.rig_log)
    if boot and first:
        print(f"boot to first prediction: guest uptime {first:.1f} s at the first prediction on the USB host "
              f"side; host wall time ~{boot[0] + first - boot[1]:.1f} s from starting QEMU "
              f"(boot to init {boot[0]:.1f} s at guest uptime {boot[1]:.1f} s)")
    if check.failures:
        print(f"hil_compare: FAIL ({len(check.failures)} problems)")
        return 1
    print("hil_compare: PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
