#!/usr/bin/env bash
# The runtime's speed table: the reference encoder (and the shipped default model) in fp32 and
# int8, on the XNNPACK and the reference executor, at 1 and 2 threads, measured side by side with
# `tlvlink bench` in one run (the machine is shared: compare ratios within one run, not across
# runs), plus the int8-vs-fp32 embedding cosine of the reference encoder on simulated frames.
#   tools/bench/runtime_table.sh [--runs N] [--rounds R] [--resolution PX] [--build DIR]
# Each configuration is benchmarked R times (rounds interleave the configurations, so a burst of
# load hits all of them alike); the table shows the median of the R medians. Needs a host build
# (build/host by default) and /usr/bin/python3 with numpy for the cosine (python3-numpy).
set -euo pipefail
cd "$(dirname "$0")/../.."
runs=300; rounds=3; res=128; build=build/host
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --resolution) res=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    *) echo "runtime_table.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
T=$build/tools/cli/tlvlink
[ -x "$T" ] || { echo "runtime_table.sh: $T missing (cmake --preset host && cmake --build --preset host)" >&2; exit 1; }
work=$(mktemp -d /tmp/tlvlink-runtime-table.XXXXXX)
trap 'rm -rf "$work"' EXIT

# The same seed gives the same float weights; the int8 form is those weights quantized.
for dtype in fp32 int8; do
  "$T" gen-reference -o "$work/ref-$dtype.tlvm" --dtype "$dtype" --resolution "$res" --seed 1 >/dev/null
done
cp firmware/models/touch-tiny-fp32.tlvm "$work/shipped-fp32.tlvm"
cp firmware/models/touch-tiny-int8.tlvm "$work/shipped-int8.tlvm"

echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; $runs runs x $rounds rounds"
results=$work/results.tsv
: >"$results"
for round in $(seq "$rounds"); do
  for model in ref shipped; do
    for dtype in fp32 int8; do
      for exec in xnnpack reference; do
        for threads in 1 2; do
          # The reference executor is single-threaded: one row is enough.
          [ "$exec" = reference ] && [ "$threads" = 2 ] && continue
          n=$runs; [ "$exec" = reference ] && n=$(( runs / 10 > 10 ? runs / 10 : 10 ))
          json=$("$T" bench "$work/$model-$dtype.tlvm" --executor "$exec" --threads "$threads" \
                   --runs "$n" --json | tr -d "\n")
          echo -e "$model\t$dtype\t$exec\t$threads\t$json" >>"$results"
        done
      done
    done
  done
done
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"

# Cosine of int8 vs fp32 embeddings on simulated GelSight frames (the renderer, not the
# synthetic blobs the int8 encoder was calibrated on).
"$T" sim touch100k -o "$work/frames" --sessions 8 --frames-per-session 4 --seed 5 \
  --vision-height 16 --vision-width 16 >/dev/null 2>&1
for f in "$work"/frames/touch/*/*.jpg; do
  b=$(basename "$(dirname "$f")")_$(basename "$f" .jpg)
  for dtype in fp32 int8; do
    "$T" infer "$work/ref-$dtype.tlvm" -i "$f" -o "$work/emb-$dtype-$b.npy" >/dev/null
  done
done

/usr/bin/python3 - "$results" "$work" <<'EOF'
import glob, json, statistics, sys
import numpy as np
rows = {}
for line in open(sys.argv[1]):
    model, dtype, ex, threads, js = line.rstrip("\n").split("\t", 4)
    rows.setdefault((model, dtype, ex, int(threads)), []).append(json.loads(js))
def pick(rs, *path):
    out = []
    for r in rs:
        v = r
        for p in path: v = v[p]
        out.append(v)
    return statistics.median(out)
print("\n| model | dtype | executor | threads | MMAC | median ms | p90 ms | GMAC/s | init ms | peak RSS MiB |")
print("|---|---|---|---|---|---|---|---|---|---|")
for key in sorted(rows, key=lambda k: (k[0], k[1], k[2] != "xnnpack", k[3])):
    rs = rows[key]
    r0 = rs[0]
    print(f"| {key[0]} | {key[1]} | {key[2]} | {key[3]} | {r0['mmac']:.1f} | {pick(rs,'median_ms'):.3f} | "
          f"{pick(rs,'p90_ms'):.3f} | {pick(rs,'gmac_per_s'):.1f} | {pick(rs,'init_ms'):.1f} | {pick(rs,'peak_rss_mib'):.0f} |")
def ratio(model, a, b):
    return pick(rows[a], 'median_ms') / pick(rows[b], 'median_ms')
print()
for model in ("ref", "shipped"):
    x = lambda d, e, t: (model, d, e, t)
    print(f"{model}: fp32/int8 time on XNNPACK 1 thread {ratio(model, x('fp32','xnnpack',1), x('int8','xnnpack',1)):.2f}x, "
          f"2 threads {ratio(model, x('fp32','xnnpack',2), x('int8','xnnpack',2)):.2f}x; "
          f"reference/XNNPACK int8 {ratio(model, x('int8','reference',1), x('int8','xnnpack',1)):.1f}x; "
          f"int8 1->2 threads {ratio(model, x('int8','xnnpack',1), x('int8','xnnpack',2)):.2f}x")
cos = []
for f in sorted(glob.glob(sys.argv[2] + "/emb-fp32-*.npy")):
    a = np.load(f).ravel().astype(np.float64)
    b = np.load(f.replace("emb-fp32-", "emb-int8-")).ravel().astype(np.float64)
    cos.append(float(a @ b / np.linalg.norm(a) / np.linalg.norm(b)))
print(f"reference encoder int8 vs fp32 embedding cosine over {len(cos)} frames: "
      f"mean {np.mean(cos):.5f}, min {np.min(cos):.5f}")
EOF
