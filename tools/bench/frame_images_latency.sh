#!/usr/bin/env bash
# tlvlinkd's per-frame latency with FrameImages off and on, side by side (issue 33 item 1):
#   tools/bench/frame_images_latency.sh [--repeats N] [--build DIR] [--baseline TLVLINKD]
# Two simulated GelSight Minis (MJPEG 3280x2464 at 25 fps, `tlvlink sim scenario`, rendered once
# into DIR/../bench/scenario) replayed at the camera's pace through the int8 model, the stream on
# a pty read by `tlvlink listen`; each repeat runs every mode once, in an order that rotates, so a
# burst of load on this shared machine hits every mode alike. Modes: off, view, input (FrameImages
# at 15 per second per sensor, the highest rate), and with --baseline the tlvlinkd of another
# build (e.g. before FrameImages existed) with images off. Per run: p50 / p99 / max of the
# daemon's own per-frame "total" latency (capture -> the record written), from its JSON lines.
# Prints per mode the median over repeats and the range, and the images the listener received.
set -euo pipefail
repeats=5 build=build/host baseline=""
while [ $# -gt 0 ]; do
  case $1 in
    --repeats) repeats=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --baseline) baseline=$2; shift 2 ;;
    *) echo "usage: $0 [--repeats N] [--build DIR] [--baseline TLVLINKD]" >&2; exit 2 ;;
  esac
done
tlvlinkd=$PWD/$build/firmware/tlvlinkd/tlvlinkd tlvlink=$PWD/$build/tools/cli/tlvlink
out=$PWD/$build/../bench
scenario=$out/scenario
mkdir -p "$out"
if [ ! -f "$scenario/B.tlvraw" ]; then
  "$tlvlink" sim scenario -o "$scenario" --overwrite --sensor gelsight-mini --grasps 3 --presses 2 --seed 2026 >/dev/null
fi

modes=(off view input)
[ -n "$baseline" ] && modes+=(baseline)

run() {  # run MODE REPEAT
  local mode=$1 r=$2 dir=$out/run-$1-$2 daemon=$tlvlinkd images=off
  rm -rf "$dir" && mkdir -p "$dir"
  case $mode in view|input) images=$mode ;; baseline) daemon=$baseline ;; esac
  local extra=""
  [ "$mode" != baseline ] && extra="frame_images = \"$images\"
frame_images_per_second = 15"
  cat >"$dir/tlvlinkd.toml" <<TOML
model = "$PWD/firmware/models/touch-tiny-int8.tlvm"
output = ["jsonl:$dir/predictions.jsonl", "pty:$dir/tty"]
command_script = "$scenario/commands.txt"
$extra
[grasp]
mode = "commanded"
[[sensor]]
name = "left"
model = "gelsight-mini"
finger = "A"
source = "replay"
device = "$scenario/A.tlvraw"
[[sensor]]
name = "right"
model = "gelsight-mini"
finger = "B"
source = "replay"
device = "$scenario/B.tlvraw"
TOML
  "$tlvlink" listen --serial "$dir/tty" --json >"$dir/stream.jsonl" 2>"$dir/listen.log" &
  local listener=$!
  "$daemon" --config "$dir/tlvlinkd.toml" 2>"$dir/daemon.log" >/dev/null
  sleep 0.5
  kill "$listener" 2>/dev/null || true
  wait "$listener" 2>/dev/null || true
  python3 - "$dir" "$mode" <<'PY'
import json, re, sys
d, mode = sys.argv[1], sys.argv[2]
log = open(f"{d}/daemon.log").read()
cpu = re.search(r"cpu %: process ([\d.]+), inference ([\d.]+), output ([\d.]+)", log)
cost = re.search(r"per image ([\d.]+) us copying on the inference thread, ([\d.]+) ms encoding", log)
# capture -> written: the line's send_ns (when the daemon wrote it) less the camera's time.
total = sorted((j["send_ns"] - j["capture_ns"]) / 1e6 for j in map(json.loads, open(f"{d}/predictions.jsonl"))
               if j["type"] == "frame_prediction")
pct = lambda p: total[min(len(total) - 1, max(0, int(round(p / 100 * len(total) + 0.5)) - 1))]  # nearest rank
images = [json.loads(l) for l in open(f"{d}/stream.jsonl") if '"type":"frame_image"' in l]
size = sorted(len(i["data"]) * 3 // 4 for i in images)
print(json.dumps({"mode": mode, "frames": len(total), "p50": pct(50), "p99": pct(99), "max": total[-1],
                  "images": len(images), "jpeg_median_bytes": size[len(size) // 2] if size else 0,
                  "jpeg_max_bytes": size[-1] if size else 0,
                  "cpu_process": float(cpu[1]) if cpu else None, "cpu_inference": float(cpu[2]) if cpu else None,
                  "copy_us": float(cost[1]) if cost else None, "encode_ms": float(cost[2]) if cost else None}))
PY
}

results=$out/results.jsonl
: >"$results"
for r in $(seq 1 "$repeats"); do
  n=${#modes[@]}
  for k in $(seq 0 $((n - 1))); do
    mode=${modes[$(((k + r) % n))]}
    run "$mode" "$r" | tee -a "$results"
  done
done
python3 - "$results" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print(f"\n{'mode':9} {'runs':>4} {'p50 ms':>8} {'p99 ms (median, range)':>26} {'max ms':>8} {'images/run':>10} {'JPEG B med/max':>15} {'cpu % proc/infer':>17}")
for mode in dict.fromkeys(r["mode"] for r in rows):
    rs = [r for r in rows if r["mode"] == mode]
    p50 = statistics.median(r["p50"] for r in rs)
    p99 = [r["p99"] for r in rs]
    cpu = [r for r in rs if r.get("cpu_process") is not None]
    cpus = (f"{statistics.median(r['cpu_process'] for r in cpu):8.1f}/{statistics.median(r['cpu_inference'] for r in cpu):.1f}"
            if cpu else "")
    cost = [r for r in rs if r.get("copy_us") is not None]
    if cost:
        cpus += (f"  per image: copy {statistics.median(r['copy_us'] for r in cost):.0f} us (inference thread), "
                 f"encode+post {statistics.median(r['encode_ms'] for r in cost):.2f} ms (encoder thread)")
    print(f"{mode:9} {len(rs):4} {p50:8.2f} {statistics.median(p99):10.2f} ({min(p99):.2f}-{max(p99):.2f}) "
          f"{statistics.median(r['max'] for r in rs):8.2f} {statistics.median(r['images'] for r in rs):10.0f} "
          f"{statistics.median(r['jpeg_median_bytes'] for r in rs):9.0f}/{max(r['jpeg_max_bytes'] for r in rs)} {cpus:>17}")
PY
