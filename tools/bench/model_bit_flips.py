#!/usr/bin/python3
"""Single-bit flips of a model file, classified by what a build of tlvlink does with them.

  tools/bench/model_bit_flips.py TLVLINK MODEL INPUT [--flips N] [--seed S] [--jobs J]

Flips N bits chosen with a seeded generator (half uniform over the file, half spread evenly over
the file in N/2 strata so every region is hit), and for each runs `TLVLINK verify` and
`TLVLINK infer MODEL -i INPUT` (the printed embedding summary and head predictions). Prints one
table row per outcome:
  rejected at load                  verify exits 1 with a model.* error (the loader refused it)
  accepted, verify fails / errors   loads, verify reports a golden mismatch / another error
  accepted, infer fails             verify passes, infer exits non-zero
  accepted, predictions changed     verify passes, a head's top class (or its label) differs
  accepted, printed values changed  same top classes, but a printed value differs
  accepted, output unchanged        infer prints exactly what the unflipped file gives
Replay with the same arguments (the seed is printed).

--targeted PYDIR flips up to 40 seeded bits in each of the places where flips used to change
predictions silently (probe weights and biases, labels, zero-shot matrices, the grasp head,
the input spec's mean/std/resize filter), located with the schema's Python module:
  flatc --python -o PYDIR runtime/model/schema/tlvm.fbs
"""
import argparse
import concurrent.futures
import os
import random
import subprocess
import sys
import tempfile


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True, errors="replace")
    return p.returncode, p.stdout, p.stderr


def infer_text(tlvlink, model, frame):
    rc, out, err = run([tlvlink, "infer", model, "-i", frame])
    return rc, out.replace(model, "MODEL"), err


def top_classes(text):
    """Each head's top class: the label after '->' on infer's 'head ...' lines."""
    return [line.split("->")[1].split(" p=")[0].strip()
            for line in text.splitlines() if line.startswith("head ") and "->" in line]


def targeted_bits(data, py_dir, seed):
    """Seeded bits inside each head / input-spec / label field of the file (see the docstring)."""
    import flatbuffers
    sys.path.insert(0, py_dir)
    from tlvlink.fb.Model import Model

    def uoffset(at):
        return flatbuffers.encode.Get(flatbuffers.packer.uoffset, data, at)

    def vector(table, slot, elem):
        o = table._tab.Offset(slot)
        if not o:
            return None
        start = table._tab.Vector(o)
        return (start, start + table._tab.VectorLen(o) * elem)

    md = Model.GetRootAsModel(data, 0).Metadata()
    regions = []
    for i in range(md.LinearHeadsLength()):
        h = md.LinearHeads(i)
        regions += [vector(h, 8, 4), vector(h, 10, 4)]  # weight, bias
        labels = h._tab.Vector(h._tab.Offset(6))
        for j in range(min(3, h.LabelsLength())):
            at = labels + 4 * j
            s = at + uoffset(at)
            regions.append((s + 4, s + 4 + uoffset(s)))
    for i in range(md.ZeroShotHeadsLength()):
        regions.append(vector(md.ZeroShotHeads(i), 10, 4))  # prompt matrix
    if md.GraspHead():
        regions.append(vector(md.GraspHead(), 8, 4))
    spec = md.Input()
    regions += [vector(spec, 22, 4), vector(spec, 24, 4)]  # mean, std
    o = spec._tab.Offset(20)  # resize filter (absent when it is the default)
    if o:
        regions.append((spec._tab.Pos + o, spec._tab.Pos + o + 1))
    rng = random.Random(seed)
    bits = []
    for a, b in (r for r in regions if r):
        bits += rng.sample(range(a * 8, b * 8), min(40, (b - a) * 8))
    return bits


def classify(args, data, bit, base_out, tmpdir):
    flipped = bytearray(data)
    flipped[bit // 8] ^= 1 << (bit % 8)
    path = os.path.join(tmpdir, f"flip_{bit}.tlvm")
    with open(path, "wb") as f:
        f.write(flipped)
    try:
        rc, out, err = run([args.tlvlink, "verify", path])
        if rc != 0:
            if "error [model." in err:
                return "rejected at load", err.strip()
            if "FAIL" in out:
                return "accepted, verify fails", out.strip().splitlines()[-1]
            return "accepted, verify errors", err.strip()
        rc, out, err = infer_text(args.tlvlink, path, args.input)
        out = out.replace(path, "MODEL")
        out = "\n".join(l for l in out.splitlines() if not l.startswith(("xnnpack executor", "reference executor")))
        if rc != 0:
            return "accepted, infer fails", err.strip()
        if out == base_out:
            return "accepted, output unchanged", ""
        if top_classes(out) != top_classes(base_out):
            return "accepted, predictions changed", ""
        return "accepted, printed values changed", ""
    finally:
        os.unlink(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("tlvlink")
    ap.add_argument("model")
    ap.add_argument("input")
    ap.add_argument("--flips", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=12)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--bits", help="comma-separated bit offsets to flip instead of a sample")
    ap.add_argument("--targeted", metavar="PYDIR", help="flip bits in the heads, input spec and labels")
    args = ap.parse_args()
    data = open(args.model, "rb").read()
    nbits = len(data) * 8
    if args.targeted:
        bits = targeted_bits(data, args.targeted, args.seed)
    elif args.bits:
        bits = [int(b) for b in args.bits.split(",")]
    else:
        rng = random.Random(args.seed)
        half = args.flips // 2
        bits = [rng.randrange(nbits) for _ in range(args.flips - half)]
        bits += [(k * nbits) // half + rng.randrange(max(1, nbits // half)) for k in range(half)]
    rc, base_out, err = infer_text(args.tlvlink, args.model, args.input)
    base_out = "\n".join(l for l in base_out.splitlines() if not l.startswith(("xnnpack executor", "reference executor")))
    if rc != 0:
        sys.exit(f"infer on the unflipped model failed: {err}")
    counts, examples = {}, {}
    with tempfile.TemporaryDirectory() as tmpdir, \
            concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for bit, (kind, detail) in zip(bits, pool.map(
                lambda b: classify(args, data, b, base_out, tmpdir), bits)):
            counts[kind] = counts.get(kind, 0) + 1
            examples.setdefault(kind, (bit, detail))
    print(f"# {args.model} ({len(data)} bytes), {len(bits)} flips, seed {args.seed}, {args.tlvlink}")
    print("| outcome | flips | example (bit: message) |")
    print("|---|---|---|")
    for kind in sorted(counts):
        bit, detail = examples[kind]
        print(f"| {kind} | {counts[kind]} | {bit}: {detail[:110]} |")


if __name__ == "__main__":
    main()
