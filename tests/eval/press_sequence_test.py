"""tools/eval/press_sequence.py on synthetic presses: what it reads of a scenario and of tlvlinkd's
output, the features, the fit, and its errors (run by ctest with Debian's python3 and numpy)."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

TOOL = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "eval", "press_sequence.py")
sys.path.insert(0, os.path.dirname(TOOL))
import press_sequence as ps  # noqa: E402

DIM = 8


def write_scenario(directory, presses, seed, sensor="digit"):
    """presses: hard flags. Each press: 12 frames of finger A; the gate's score rises to a peak at
    frame 8. Hard and soft presses share their peak embedding (one frame cannot tell them) and
    differ in their first frame's (the sequence can). Frames outside events, out of contact or
    without an embedding are written too, and must be ignored."""
    rng = np.random.default_rng(seed)
    os.makedirs(directory, exist_ok=True)
    truth = [{"type": "scenario", "sensor": sensor}]
    out = [{"type": "stats"}]
    seq = 0
    for e, hard in enumerate(presses):
        truth.append({"type": "event", "id": e, "kind": "press",
                      "hard_soft": "hard" if hard else "soft", "material": "m"})
        truth.append({"type": "frame", "finger": "A", "seq": seq, "event": -1, "force_n": 0,
                      "area_mm2": 0})
        out.append({"type": "frame_prediction", "frame_sequence": seq, "contact": True,
                    "gate_score_dn": 99.0, "embedding": [9.0] * DIM, "heads": []})  # no event
        seq += 1
        for k in range(12):
            peak = rng.normal(0, 1, DIM)
            emb = peak.copy()
            if k == 0:
                emb[0] = (2.0 if hard else -2.0) + rng.normal(0, 0.3)
            truth.append({"type": "frame", "finger": "A", "seq": seq, "event": e,
                          "force_n": 1.0 + k, "area_mm2": 10.0 + k})
            truth.append({"type": "frame", "finger": "B", "seq": seq, "event": -1,
                          "force_n": 0, "area_mm2": 0})
            out.append({"type": "frame_prediction", "frame_sequence": seq, "contact": True,
                        "gate_score_dn": 10.0 - abs(k - 8), "embedding": emb.tolist(),
                        "heads": [{"name": "hard_soft", "top_label": "hard"}]})
            seq += 1
        out.append({"type": "frame_prediction", "frame_sequence": seq - 1, "contact": False,
                    "gate_score_dn": 0.0, "heads": []})  # out of contact: ignored
    with open(f"{directory}/truth.jsonl", "w") as f:
        f.writelines(json.dumps(r) + "\n" for r in truth)
    with open(f"{directory}/press-offline.jsonl", "w") as f:
        f.writelines(json.dumps(r) + "\n" for r in out)


def test_reads_each_press_with_its_frames_in_contact(tmp_path):
    write_scenario(tmp_path / "a", [True, False, True], seed=1)
    presses, total = ps.load_scenario(str(tmp_path / "a"), "press-offline.jsonl")
    assert total == 3
    assert [p.hard for p in presses] == [True, False, True]
    assert all(p.sensor == "digit" and len(p.frames) == 12 for p in presses)
    assert [x[0] for x in presses[0].frames] == list(range(1, 13))  # in order, no stray frame
    thinned, _ = ps.load_scenario(str(tmp_path / "a"), "press-offline.jsonl", {"digit": 3})
    assert [x[0] for x in thinned[0].frames] == [3, 6, 9, 12]


def test_the_sequence_tells_what_one_frame_cannot(tmp_path):
    rng = np.random.default_rng(2)
    presses = []
    for i in range(3):
        write_scenario(tmp_path / f"s{i}", list(rng.integers(0, 2, 40).astype(bool)), seed=10 + i)
        presses += ps.load_scenario(str(tmp_path / f"s{i}"), "press-offline.jsonl")[0]
    y = np.array([p.hard for p in presses], float)
    train, test = slice(0, 80), slice(80, 120)
    scores = {}
    for kind in ("peak", "peak+first"):
        x = np.stack([ps.features(p, kind) for p in presses])
        predict = ps.fit_logistic(x[train], y[train], 0.1)
        scores[kind] = np.mean((predict(x[test]) > 0) == (y[test] == 1))
    # Tolerance: the first frame separates the classes by 4 sigma, so the sequence head is right
    # on (nearly) every press; the peak is noise only, so one frame stays near chance (40 presses:
    # +-16 points is 2 sigma).
    assert scores["peak+first"] >= 0.95
    assert scores["peak"] <= 0.75
    assert ps.features(presses[0], "peak+first").shape == (2 * DIM,)
    assert ps.features(presses[0], "peak+rise").shape == (4 * DIM,)


def test_the_program_prints_every_feature_set_and_refuses_bad_input(tmp_path):
    rng = np.random.default_rng(3)
    for i in range(3):
        write_scenario(tmp_path / f"s{i}", list(rng.integers(0, 2, 20).astype(bool)), seed=20 + i)
    dirs = [str(tmp_path / f"s{i}") for i in range(3)]
    run = subprocess.run([sys.executable, TOOL, "--train", ",".join(dirs[:2]), "--test", dirs[2]],
                         capture_output=True, text=True, check=True)
    for kind in ps.FEATURES:
        assert any(line.startswith(kind + " ") for line in run.stdout.splitlines()), run.stdout
    bad = subprocess.run([sys.executable, TOOL, "--thin", "digit=0", "--train", dirs[0], "--test",
                          dirs[1]], capture_output=True, text=True)
    assert bad.returncode == 2 and "--thin digit=0" in bad.stderr
    (tmp_path / "empty").mkdir()
    (tmp_path / "empty" / "truth.jsonl").write_text((tmp_path / "s0" / "truth.jsonl").read_text())
    (tmp_path / "empty" / "press-offline.jsonl").write_text('{"type": "stats"}\n')
    empty = subprocess.run([sys.executable, TOOL, "--train", str(tmp_path / "empty"), "--test",
                            dirs[1]], capture_output=True, text=True)
    assert empty.returncode != 0 and "no embeddings of presses" in empty.stderr


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
