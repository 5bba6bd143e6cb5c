#!/usr/bin/env bash
# Hard/soft from a press sequence, measured (issue 29, item 6): scenarios of single-finger presses
# (GelSight Mini and DIGIT, each on its own unseen sensor instances), played by tlvlinkd with
# `embedding = true`, then press_sequence.py: logistic heads over one frame of each press and over
# its sequence (first contact and peak, the rise), fitted on the training scenarios and scored per
# press on the test ones, with 95 % intervals.
#   tools/eval/press_sequence.sh OUT [MODEL] [--path offline|live]
#   offline (default): the exact processed frames; live: the cameras' raw output (Mini: MJPEG
#   3280x2464; DIGIT: YUYV) through the board's decoder, as on a robot
# Environment: TLVLINK_BUILD (default build/host). Scenarios already played in OUT are reused.
# About 40 minutes on 2 cores (rendering ~22, playing 8 x 6.5 min four at a time); ~25 GB in OUT.
set -euo pipefail
cd "$(dirname "$0")/../.."
usage="usage: press_sequence.sh OUT [MODEL] [--path offline|live]"
out=${1:?$usage}
shift
model=firmware/models/touch-tiny-int8.tlvm
if [ $# -gt 0 ] && [ "$1" != --path ]; then model=$1; shift; fi
path=offline
if [ $# -gt 0 ]; then
  if [ "$1" != --path ] || [ $# -ne 2 ] || { [ "$2" != offline ] && [ "$2" != live ]; }; then
    echo "press_sequence: $usage" >&2
    exit 2
  fi
  path=$2
fi
# sensor:seed:presses[:markers]; seeds unlike any set's or live_vs_offline.sh's.
train=(gelsight-mini:401:150:markers gelsight-mini:402:150 digit:403:150:markers digit:404:150)
test=(digit:405:150:markers digit:406:150 gelsight-mini:407:150:markers gelsight-mini:408:150)
build=${TLVLINK_BUILD:-build/host}
tlvlink=$build/tools/cli/tlvlink
tlvlinkd=$build/firmware/tlvlinkd/tlvlinkd
for b in "$tlvlink" "$tlvlinkd"; do
  [ -x "$b" ] || { echo "press_sequence: $b missing (cmake --build --preset host)" >&2; exit 1; }
done
[ -f "$model" ] || { echo "press_sequence: model $model missing" >&2; exit 2; }
python3 -c 'import numpy' 2>/dev/null || { echo "press_sequence: python3-numpy missing (tools/setup/install_deps.sh)" >&2; exit 1; }
mkdir -p "$out"
out=$(realpath "$out")
model=$(realpath "$model")
t0=$(date +%s)

dir_of() { IFS=: read -r sensor seed _ _ <<<"$1"; echo "$out/$sensor-$seed"; }

render() {  # spec
  local sensor seed presses markers dir args
  IFS=: read -r sensor seed presses markers <<<"$1"
  dir=$(dir_of "$1")
  args=(--sensor "$sensor" --seed "$seed" --grasps 0 --presses "$presses" --offline)
  [ "${markers:-}" = markers ] && args+=(--markers)
  if [ -f "$dir/truth.jsonl" ] && [ "$(cat "$dir/args" 2>/dev/null)" = "${args[*]}" ]; then return; fi
  echo "== render $1"
  "$tlvlink" sim scenario -o "$dir" "${args[@]}" --overwrite | tail -1
  echo "${args[*]}" >"$dir/args"
  rm -f "$dir"/press-*.jsonl
}

play() {  # spec: finger A in real time (a replay faster than the camera drops frames at the
          # queue), every encoded frame's embedding reported
  local sensor dir w=320 h=240 run
  IFS=: read -r sensor _ <<<"$1"
  dir=$(dir_of "$1")
  run=$dir/press-$path
  [ "$sensor" = digit ] && { w=240; h=320; }
  [ -s "$run.jsonl" ] && [ "$(cat "$run.model" 2>/dev/null)" = "$model" ] && return
  {
    printf 'model = "%s"\noutput = ["jsonl:%s"]\nverify_model = false\nembedding = true\n' \
      "$model" "$run.jsonl.partial"
    printf '[grasp]\nmode = "off"\n[[sensor]]\nname = "left"\nmodel = "%s"\nfinger = "A"\n' "$sensor"
    if [ "$path" = live ]; then  # the sensor model's own camera format and view
      printf 'source = "replay"\ndevice = "%s"\n' "$dir/A.tlvraw"
    else
      printf 'source = "replay"\ndevice = "%s"\nformat = "rgb24"\nwidth = %d\nheight = %d\n' \
        "$dir/A.offline.tlvraw" "$w" "$h"
      printf 'crop = 0.0\njpeg_scale = 1\norientation = "upright"\n'
    fi
  } >"$run.toml"
  rm -f "$run.jsonl.partial"
  "$tlvlinkd" --config "$run.toml" 2>"$run.log" >/dev/null ||
    { tail -5 "$run.log"; echo "press_sequence: tlvlinkd failed ($run.log)" >&2; return 1; }
  mv "$run.jsonl.partial" "$run.jsonl"
  echo "$model" >"$run.model"
  echo "   $1 ($path): $(grep -E '^ *drops:' "$run.log" | sed 's/^ *//')"
}

specs=("${train[@]}" "${test[@]}")
for spec in "${specs[@]}"; do render "$spec"; done
echo "== tlvlinkd: ${#specs[@]} scenarios ($path path), four at a time in real time"
pids=()
for spec in "${specs[@]}"; do
  play "$spec" &
  pids+=($!)
  if [ ${#pids[@]} -eq 4 ]; then for p in "${pids[@]}"; do wait "$p"; done; pids=(); fi
done
for p in "${pids[@]}"; do wait "$p"; done

join() { local IFS=,; echo "$*"; }
train_dirs=(); for s in "${train[@]}"; do train_dirs+=("$(dir_of "$s")"); done
test_dirs=(); for s in "${test[@]}"; do test_dirs+=("$(dir_of "$s")"); done
echo
echo "== model $model, $path path"
python3 tools/eval/press_sequence.py --predictions "press-$path.jsonl" \
  --train "$(join "${train_dirs[@]}")" --test "$(join "${test_dirs[@]}")" | tee "$out/press_sequence-$path.txt"
echo "press_sequence: $(( $(date +%s) - t0 )) s; $out/press_sequence-$path.txt"
