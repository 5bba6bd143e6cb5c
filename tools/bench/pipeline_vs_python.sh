#!/usr/bin/env bash
# tlvlink's camera-to-prediction path against the pipeline a Python user would write, on the same
# recorded camera frames and the same model weights, one core each, interleaved in rounds so the
# machine's load hits both alike; prints medians over the rounds and the ratios.
#   tools/bench/pipeline_vs_python.sh [--frames N] [--rounds R] [--out DIR]
# Needs a build with benchmarks (the host preset) and tools/setup/install_deps.sh bench.
set -euo pipefail
cd "$(dirname "$0")/../.."
frames=30 rounds=3 out=build/bench/pipeline
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "pipeline_vs_python.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
bash tools/setup/install_deps.sh bench >/dev/null
bench=build/host/tools/bench/pipeline/tlvlink_pipeline_bench
[ -x "$bench" ] || { echo "build the host preset first (cmake --build --preset host)" >&2; exit 1; }
mkdir -p "$out"
rm -rf "$out/frames"
"$bench" --frames "$out/frames" --make "$frames" --rounds 1 >/dev/null
for r in $(seq 1 "$rounds"); do
  "$bench" --frames "$out/frames" --rounds 2 --json "$out/tlvlink-$r.json" >"$out/tlvlink-$r.txt"
  (cd tools/bench/python_peer && /usr/bin/python3 peer.py --frames "../../../$out/frames" \
     --model ../../../firmware/models/touch-tiny-fp32.tlvm --schema ../../../runtime/model/schema/tlvm.fbs \
     --rounds 2 --json "../../../$out/python-$r.json") >"$out/python-$r.txt"
  echo "round $r of $rounds done" >&2
done
/usr/bin/python3 - "$out" "$rounds" <<'PY'
import json, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
rows = {}
for r in range(1, rounds + 1):
    for name in ("tlvlink", "python"):
        for row in json.load(open("%s/%s-%d.json" % (out, name, r)))["rows"]:
            rows.setdefault(row["label"], []).append(row)
med = {k: {f: statistics.median(x[f] for x in v) for f in ("median_ms", "p99_ms", "cpu_ms", "fps")} for k, v in rows.items()}
print("%-48s %10s %10s %10s %10s" % ("median of %d rounds, one core" % rounds, "ms/frame", "p99 ms", "CPU ms", "frames/s"))
for k, v in med.items():
    print("%-48s %10.2f %10.2f %10.2f %10.1f" % (k, v["median_ms"], v["p99_ms"], v["cpu_ms"], v["fps"]))
ours = med["whole frame: decode, preprocess, encoder, heads"]
for k in ("python full-size decode", "python IMREAD_REDUCED_COLOR_8 decode"):
    p = med[k]
    print("tlvlink vs %-36s frames/s x%.2f, p99 x%.2f lower, CPU/frame x%.2f lower" %
          (k, ours["fps"] / p["fps"], p["p99_ms"] / ours["p99_ms"], p["cpu_ms"] / ours["cpu_ms"]))
full = med["decode + preprocess (full-size decode)"]["median_ms"]
scaled = med["decode + preprocess (pipeline's scale)"]["median_ms"]
print("decode + preprocess of one frame: scaled and cropped %.2f ms vs full-size %.2f ms: x%.2f" % (scaled, full, full / scaled))
PY
