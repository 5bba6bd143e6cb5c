#!/usr/bin/env bash
# Hard/soft from a press sequence, measured (issue 29, item 6): scenarios of single-finger presses
# (GelSight Mini and DIGIT, each on its own unseen sensor instances), played by tlvlinkd from their
# processed frames with `embedding = true`, then press_sequence.py: logistic heads over one frame
# of each press and over its sequence (first contact and peak, the rise), fitted on the training
# scenarios and scored per press on the test ones, with 95 % intervals.
#   tools/eval/press_sequence.sh OUT [MODEL]
# Environment: TLVLINK_BUILD (default build/host). Scenarios already played in OUT are reused.
# About 40 minutes on 2 cores (rendering ~22, playing 8 x 6.5 min four at a time); ~25 GB in OUT.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: press_sequence.sh OUT [MODEL]}
model=${2:-firmware/models/touch-tiny-int8.tlvm}
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
  rm -f "$dir/press.jsonl"
}

play() {  # spec: finger A's exact processed frames, in real time (a replay faster than the
          # camera drops frames at the queue), every encoded frame's embedding reported
  local sensor dir w=320 h=240
  IFS=: read -r sensor _ <<<"$1"
  dir=$(dir_of "$1")
  [ "$sensor" = digit ] && { w=240; h=320; }
  [ -s "$dir/press.jsonl" ] && [ "$(cat "$dir/press.model" 2>/dev/null)" = "$model" ] && return
  cat >"$dir/press.toml" <<EOF
model = "$model"
output = ["jsonl:$dir/press.jsonl.partial"]
verify_model = false
embedding = true
[grasp]
mode = "off"
[[sensor]]
name = "left"
model = "$sensor"
finger = "A"
source = "replay"
device = "$dir/A.offline.tlvraw"
format = "rgb24"
width = $w
height = $h
crop = 0.0
jpeg_scale = 1
orientation = "upright"
EOF
  rm -f "$dir/press.jsonl.partial"
  "$tlvlinkd" --config "$dir/press.toml" 2>"$dir/press.log" >/dev/null ||
    { tail -5 "$dir/press.log"; echo "press_sequence: tlvlinkd failed ($dir/press.log)" >&2; return 1; }
  mv "$dir/press.jsonl.partial" "$dir/press.jsonl"
  echo "$model" >"$dir/press.model"
  echo "   $1: $(grep -E '^ *drops:' "$dir/press.log" | sed 's/^ *//')"
}

specs=("${train[@]}" "${test[@]}")
for spec in "${specs[@]}"; do render "$spec"; done
echo "== tlvlinkd: ${#specs[@]} scenarios, four at a time in real time"
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
echo "== model $model"
python3 tools/eval/press_sequence.py --train "$(join "${train_dirs[@]}")" \
  --test "$(join "${test_dirs[@]}")" | tee "$out/press_sequence.txt"
echo "press_sequence: $(( $(date +%s) - t0 )) s; $out/press_sequence.txt"
