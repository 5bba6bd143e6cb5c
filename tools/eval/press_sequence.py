#!/usr/bin/env python3
"""Hard/soft from a press sequence, measured (issue 29, item 6): does what a press shows over its
frames tell hard from soft better than one frame does?

Reads scenarios of single-finger presses (`tlvlink sim scenario --grasps 0`) that tlvlinkd played
with `embedding = true` (press_sequence.sh makes both): per press, the embeddings of the frames its
contact gate let through, in order. Each feature set below is a logistic head (L2 chosen by
leave-one-scenario-out on the training scenarios, so every fold has sensors it did not see),
fitted on all training scenarios and scored once on the test scenarios, per press, with 95 %
intervals from a bootstrap over presses and paired differences against one frame.

  press_sequence.py [--predictions NAME] [--thin SENSOR=N] --train DIR,DIR... --test DIR,DIR...
  (DIR: the scenario's truth.jsonl and tlvlinkd's output NAME, default press-offline.jsonl)
"""
import argparse
import json
import sys

import numpy as np

# Feature sets: what a head over one press could read. "peak" is one frame (the per-frame heads'
# view at its best: the frames around the strongest imprint); "first" the first frame the gate let
# through; the others read the sequence. "oracle" is the simulator's truth (force and contact
# area along the rise), which no head sees: what the physics leaves in the sequence at all.
FEATURES = ["peak", "first", "mean", "peak+first", "peak+rise", "oracle"]
L2_GRID = [1e-3, 1e-2, 1e-1, 1.0]
BOOTSTRAP = 2000


class Press:
    def __init__(self, scenario, sensor, hard, material, frames):
        self.scenario, self.sensor, self.hard, self.material = scenario, sensor, hard, material
        # (sequence, gate score DN, embedding, force N, area mm2, the model's hard/soft head's
        # answer as tlvlinkd reported it: smoothed over the contact so far), in order
        self.frames = frames


def load_scenario(directory, predictions, thin=None):
    """The presses of one scenario with the embeddings tlvlinkd gave their frames in contact."""
    events, truth, sensor = {}, {}, "?"
    with open(f"{directory}/truth.jsonl") as f:
        for line in f:
            r = json.loads(line)
            if r["type"] == "scenario":
                sensor = r["sensor"]
            elif r["type"] == "event" and r["kind"] == "press":
                events[r["id"]] = r
            elif r["type"] == "frame" and r["finger"] == "A":
                truth[r["seq"]] = (r["event"], r["force_n"], r["area_mm2"])
    frames = {}
    with open(f"{directory}/{predictions}") as f:
        for line in f:
            r = json.loads(line)
            if r.get("type") != "frame_prediction" or not r["contact"] or "embedding" not in r:
                continue
            event, force, area = truth.get(r["frame_sequence"], (-1, 0.0, 0.0))
            if event not in events:
                continue
            if thin and r["frame_sequence"] % thin.get(sensor, 1) != 0:
                continue  # as a camera of a lower frame rate would see the press
            head = [h["top_label"] for h in r["heads"] if h["name"] == "hard_soft"]
            frames.setdefault(event, []).append(
                (r["frame_sequence"], r["gate_score_dn"], np.asarray(r["embedding"], np.float32),
                 force, area, head[0] == "hard" if head else None))
    if not frames:
        sys.exit(f"press_sequence: {directory}/{predictions} has no embeddings of presses "
                 "(tlvlinkd with embedding = true on the scenario's finger A)")
    presses = []
    for event_id, event in sorted(events.items()):
        fr = sorted(frames.get(event_id, []), key=lambda x: x[0])
        if len(fr) >= 4:  # a press the gate saw for a few frames at least
            presses.append(
                Press(directory, sensor, event["hard_soft"] == "hard", event["material"], fr))
    return presses, len(events)


def features(press, kind):
    emb = np.stack([x[2] for x in press.frames])
    gate = np.array([x[1] for x in press.frames])
    k = int(np.argmax(gate))
    peak = emb[max(0, k - 2):k + 3].mean(0)
    if kind == "peak":
        return peak
    if kind == "first":
        return emb[0]
    if kind == "mean":
        return emb.mean(0)
    if kind == "peak+first":
        return np.concatenate([peak, peak - emb[0]])
    if kind == "peak+rise":  # the frames where the rise passes 1/4, 1/2, 3/4 of the peak's score
        rise = [next(j for j in range(k + 1) if gate[j] >= q * gate[k]) for q in (0.25, 0.5, 0.75)]
        return np.concatenate([peak] + [peak - emb[j] for j in rise])
    if kind == "oracle":
        force = np.array([x[3] for x in press.frames])
        area = np.array([x[4] for x in press.frames])
        top = int(np.argmax(force))
        rise = [j for j in range(top + 1) if force[j] > 0.05 * force[top] and area[j] > 0]
        lf, la = np.log(force[rise]), np.log(area[rise])
        slope = np.polyfit(lf, la, 1)[0] if len(rise) > 2 else 0.0
        return np.array([np.log(force[top]), np.log(max(area[top], 1e-3)), slope,
                         la.mean() - lf.mean()])
    raise ValueError(kind)


def fit_logistic(x, y, l2):
    """L2-regularised logistic regression on standardised features (Newton's method: convex, a
    few steps). Returns the scoring function (logit > 0: hard)."""
    mu, sd = x.mean(0), x.std(0) + 1e-6

    def design(v):
        return np.hstack([(v - mu) / sd, np.ones((len(v), 1))])

    z = design(x)
    w = np.zeros(z.shape[1])
    reg = l2 * np.eye(len(w))
    reg[-1, -1] = 0  # the bias is not shrunk
    for _ in range(50):
        p = 1 / (1 + np.exp(-np.clip(z @ w, -30, 30)))
        grad = z.T @ (p - y) / len(y) + reg @ w
        hess = (z * (p * (1 - p))[:, None]).T @ z / len(y) + reg + 1e-9 * np.eye(len(w))
        step = np.linalg.solve(hess, grad)
        w -= step
        if np.abs(step).max() < 1e-7:
            break
    return lambda v: design(v) @ w


def choose_l2(x, y, groups):
    """The L2 whose leave-one-scenario-out accuracy on the training scenarios is best."""
    best = None
    for l2 in L2_GRID:
        correct = np.zeros(len(y), bool)
        for g in np.unique(groups):
            held = groups == g
            correct[held] = (fit_logistic(x[~held], y[~held], l2)(x[held]) > 0) == (y[held] == 1)
        if best is None or correct.mean() > best[1]:
            best = (l2, correct.mean())
    return best


def interval(values, resamples):
    return np.percentile([values[r].mean() for r in resamples], [2.5, 97.5]) * 100


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--predictions", default="press-offline.jsonl",
                    help="tlvlinkd's output in each directory (embedding = true)")
    ap.add_argument("--thin", action="append", default=[], metavar="SENSOR=N",
                    help="keep only every N-th frame of that sensor model's scenarios (a slower "
                         "camera); repeatable")
    ap.add_argument("--train", required=True, help="comma-separated scenario directories")
    ap.add_argument("--test", required=True, help="comma-separated scenario directories")
    a = ap.parse_args()
    train_dirs, test_dirs = a.train.split(","), a.test.split(",")
    thin = {}
    for t in a.thin:
        sensor, _, n = t.partition("=")
        if not n.isdigit() or int(n) < 1:
            ap.error(f"--thin {t}: expected SENSOR=N with N >= 1, e.g. digit=5")
        thin[sensor] = int(n)
    train, test = [], []
    for dirs, into in ((train_dirs, train), (test_dirs, test)):
        for d in dirs:
            presses, total = load_scenario(d, a.predictions, thin)
            into.extend(presses)
            share = np.median([p.frames[0][3] / max(x[3] for x in p.frames) for p in presses])
            print(f"{d}: {len(presses)} of {total} presses seen for >= 4 frames; the first in "
                  f"contact at a median {100 * share:.1f} % of the peak force")
    y_train = np.array([p.hard for p in train], float)
    y_test = np.array([p.hard for p in test], float)
    groups = np.array([train_dirs.index(p.scenario) for p in train])
    majority = 1.0 if y_train.mean() >= 0.5 else 0.0
    majority_correct = (y_test == majority).astype(float)
    print(f"train {len(train)} presses ({100 * y_train.mean():.1f} % hard), test {len(test)} "
          f"({100 * y_test.mean():.1f} % hard); the majority class scores "
          f"{100 * majority_correct.mean():.1f} % on test")
    rng = np.random.default_rng(1)
    resamples = [rng.integers(0, len(test), len(test)) for _ in range(BOOTSTRAP)]
    # Each sensor model's presses apart (they need not agree), resampled once for every row.
    sensors = {}
    for sensor in sorted({p.sensor for p in test}):
        on = np.flatnonzero([p.sensor == sensor for p in test])
        sensors[sensor] = (on, [on[rng.integers(0, len(on), len(on))] for _ in range(BOOTSTRAP)])

    def per_sensor(correct):
        out = ""
        for sensor, (on, draws) in sensors.items():
            d = correct - majority_correct
            lo, hi = interval(d, draws)
            out += (f"  {sensor} {100 * correct[on].mean():.1f} (majority "
                    f"{100 * majority_correct[on].mean():.1f}: {100 * d[on].mean():+.1f} "
                    f"[{lo:+.1f}, {hi:+.1f}], n {len(on)})")
        return out

    # The model's own per-frame head, as tlvlinkd reports it, at the first frame and at the peak.
    for name, pick in (("first", lambda p: p.frames[0]),
                       ("peak", lambda p: p.frames[int(np.argmax([x[1] for x in p.frames]))])):
        answers = [pick(p)[5] for p in test]
        if None in answers:
            continue
        correct = (np.array(answers) == (y_test == 1)).astype(float)
        lo, hi = interval(correct, resamples)
        d = correct - majority_correct
        dlo, dhi = interval(d, resamples)
        print(f"the model's hard/soft head at the {name} frame: {100 * correct.mean():5.1f} % "
              f"[{lo:4.1f}, {hi:4.1f}]  vs majority {100 * d.mean():+5.1f} [{dlo:+5.1f}, {dhi:+5.1f}]"
              + per_sensor(correct))
    one_frame = None
    for kind in FEATURES:
        x_train = np.stack([features(p, kind) for p in train])
        x_test = np.stack([features(p, kind) for p in test])
        l2, cv = choose_l2(x_train, y_train, groups)
        correct = ((fit_logistic(x_train, y_train, l2)(x_test) > 0) == (y_test == 1)).astype(float)
        lo, hi = interval(correct, resamples)
        balanced = 0.5 * (correct[y_test == 1].mean() + correct[y_test == 0].mean())
        line = (f"{kind:11s} test {100 * correct.mean():5.1f} % [{lo:4.1f}, {hi:4.1f}]  balanced "
                f"{100 * balanced:5.1f}  (L2 {l2:g}, cv {100 * cv:4.1f})")
        for name, base in (("one frame", one_frame), ("majority", majority_correct)):
            if base is None:
                continue
            d = correct - base
            lo, hi = interval(d, resamples)
            line += f"  vs {name} {100 * d.mean():+5.1f} [{lo:+5.1f}, {hi:+5.1f}]"
        print(line + per_sensor(correct))
        if kind == "peak":
            one_frame = correct


if __name__ == "__main__":
    main()
