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
# About 25 minutes on 2 cores (rendering ~22; the plays: ~4 min live, under 1 offline); ~25 GB in OUT.
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
# sensor:seed:presses[:markers]
train=(gelsight-mini:401:150:markers gelsight-mini:402:150 digit:403:150:markers digit:404:150)
test=(digit:405:150:markers digit:406:150 gelsight-mini:407:150:markers gelsight-mini:408:150)
# shellcheck source=tools/eval/press_scenarios.sh
. tools/eval/press_scenarios.sh
press_tools "${TLVLINK_BUILD:-build/host}"
[ -f "$model" ] || { echo "press_sequence: model $model missing" >&2; exit 2; }
python3 -c 'import numpy' 2>/dev/null || { echo "press_sequence: python3-numpy missing (tools/setup/install_deps.sh)" >&2; exit 1; }
mkdir -p "$out"
out=$(realpath "$out")
model=$(realpath "$model")
t0=$(date +%s)

specs=("${train[@]}" "${test[@]}")
for spec in "${specs[@]}"; do press_render "$out" "$spec"; done
echo "== tlvlinkd: ${#specs[@]} scenarios ($path path), every frame, ${TLVLINK_PLAYS:-2} at a time"
press_play_all "$out" "$model" "$path" "press-$path" "${specs[@]}"

join() { local IFS=,; echo "$*"; }
train_dirs=(); for s in "${train[@]}"; do train_dirs+=("$(press_dir "$out" "$s")"); done
test_dirs=(); for s in "${test[@]}"; do test_dirs+=("$(press_dir "$out" "$s")"); done
echo
echo "== model $model, $path path"
python3 tools/eval/press_sequence.py --predictions "press-$path.jsonl" \
  --train "$(join "${train_dirs[@]}")" --test "$(join "${test_dirs[@]}")" | tee "$out/press_sequence-$path.txt"
echo "press_sequence: $(( $(date +%s) - t0 )) s; $out/press_sequence-$path.txt"
