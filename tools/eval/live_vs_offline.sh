#!/usr/bin/env bash
# Live = offline, measured (issue 29): scenarios of two simulated fingers (GelSight Mini and
# DIGIT, each scenario on its own two sensor instances, none of them in the training set's),
# each played by tlvlinkd three times from the same scenes, side by side:
#   live     the cameras' raw output (Mini: MJPEG 3280x2464 q90; DIGIT: YUYV), decoded by the
#            board's decoder, as on a robot
#   offline  the processed frames of the upright view, exactly (replayed as an RGB24 camera of
#            the view's size): what the model reads offline from the very same frames
#   dataset  the same frames as the datasets store them (JPEG q90, 4:2:0: the bytes `tlvlink
#            eval` reads from a generated set), replayed as an MJPEG camera
# with the gripper controller's closed / lifting marks of every grasp (grasp mode "commanded",
# the scenario's commands.txt as tlvlinkd's command_script), and scored against the truth with
# `tlvlink score --offline`: live vs offline per head and for grasps with 95 % intervals
# (bootstrap over events; the targets), the live run's contact gate, and live vs the datasets'
# copy (live_vs_dataset.txt: what the datasets' codec alone moves).
#   tools/eval/live_vs_offline.sh OUT [MODEL] [-- SCENARIO...]
#   SCENARIO: sensor:seed:grasps:presses[:markers], default the four below (~240 events)
# Environment: TLVLINK_BUILD (default build/host). Scenarios already rendered in OUT are reused.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: live_vs_offline.sh OUT [MODEL] [-- SCENARIO...]}
shift
model=firmware/models/touch-tiny-int8.tlvm
if [ $# -gt 0 ] && [ "$1" != "--" ]; then model=$1; shift; fi
[ "${1:-}" = "--" ] && shift
scenarios=("$@")
if [ ${#scenarios[@]} -eq 0 ]; then
  # 120 grasps + 120 presses over four sensor pairs; seeds unlike any set's (1, 3, 2026, 2027).
  scenarios=(gelsight-mini:301:30:30:markers gelsight-mini:302:30:30 digit:303:30:30:markers
             digit:304:30:30)
fi
build=${TLVLINK_BUILD:-build/host}
tlvlink=$build/tools/cli/tlvlink
tlvlinkd=$build/firmware/tlvlinkd/tlvlinkd
for b in "$tlvlink" "$tlvlinkd"; do
  [ -x "$b" ] || { echo "live_vs_offline: $b missing (cmake --build --preset host)" >&2; exit 1; }
done
[ -f "$model" ] || { echo "live_vs_offline: model $model missing" >&2; exit 2; }
mkdir -p "$out"
out=$(realpath "$out")
model=$(realpath "$model")

# One sensor section: how the run reads its finger's recording.
sensor_toml() {  # name finger recording sensor path(live|offline|dataset)
  local name=$1 finger=$2 rec=$3 sensor=$4 path=$5
  printf '[[sensor]]\nname = "%s"\nmodel = "%s"\nfinger = "%s"\nsource = "replay"\ndevice = "%s"\n' \
    "$name" "$sensor" "$finger" "$rec"
  if [ "$path" != live ]; then
    local w=320 h=240 format=rgb24
    [ "$sensor" = digit ] && { w=240; h=320; }
    [ "$path" = dataset ] && format=mjpeg
    printf 'format = "%s"\nwidth = %d\nheight = %d\ncrop = 0.0\njpeg_scale = 1\norientation = "upright"\n' "$format" "$w" "$h"
  fi
}

paths=(live offline dataset)  # tlvlinkd runs per scenario, side by side
truths=(); lives=(); offlines=(); datasets=()
t0=$(date +%s)
for spec in "${scenarios[@]}"; do
  IFS=: read -r sensor seed grasps presses markers <<<"$spec"
  dir=$out/$sensor-$seed
  args=(--sensor "$sensor" --seed "$seed" --grasps "$grasps" --presses "$presses" --offline)
  [ "${markers:-}" = markers ] && args+=(--markers)
  if [ ! -f "$dir/truth.jsonl" ] || [ ! -f "$dir/A.dataset.tlvraw" ] || [ ! -f "$dir/commands.txt" ] || [ "$(cat "$dir/args" 2>/dev/null)" != "${args[*]}" ]; then
    echo "== render $spec"
    "$tlvlink" sim scenario -o "$dir" "${args[@]}" --overwrite | tail -1  # this script's own folder
    echo "${args[*]}" >"$dir/args"
  fi
  # The paths play at the cameras' pace, side by side (a daemon uses ~25 % of a core): the
  # grasp detector and the smoothing reason in the recorded time, so the replay is real time.
  pids=()
  for path in "${paths[@]}"; do
    suffix=""; [ "$path" != live ] && suffix=.$path
    {
      # The gripper controller's closed / lifting marks (commands.txt) start each grasp: a grasp
      # the contact gate cannot see (a smooth flat face filling the gel) is still predicted.
      printf 'model = "%s"\noutput = ["jsonl:%s"]\nverify_model = false\ncommand_script = "%s"\n[grasp]\nmode = "commanded"\n' \
        "$model" "$dir/$path.jsonl" "$dir/commands.txt"
      sensor_toml left A "$dir/A$suffix.tlvraw" "$sensor" "$path"
      sensor_toml right B "$dir/B$suffix.tlvraw" "$sensor" "$path"
    } >"$dir/$path.toml"
    rm -f "$dir/$path.jsonl"
    "$tlvlinkd" --config "$dir/$path.toml" 2>"$dir/$path.log" >/dev/null &
    pids+=($!)
  done
  echo "== tlvlinkd $spec: live, offline and dataset in real time ($(grep -o '"frames":[0-9]*' "$dir/truth.jsonl" | head -1 | cut -d: -f2) frames per finger)"
  for i in "${!paths[@]}"; do
    path=${paths[$i]}
    wait "${pids[$i]}" || { tail -5 "$dir/$path.log"; echo "live_vs_offline: tlvlinkd failed ($dir/$path.log)" >&2; exit 1; }
    echo "   $path: $(grep -E '^ *drops:' "$dir/$path.log" | sed 's/^ *//')"
  done
  truths+=(--truth "$dir/truth.jsonl"); lives+=(--predictions "$dir/live.jsonl")
  offlines+=(--offline "$dir/offline.jsonl"); datasets+=(--offline "$dir/dataset.jsonl")
done
echo
echo "== model $model"
"$tlvlink" score "${truths[@]}" "${lives[@]}" "${offlines[@]}" | tee "$out/live_vs_offline.txt"
"$tlvlink" score "${truths[@]}" "${lives[@]}" "${offlines[@]}" --json >"$out/live_vs_offline.json"
# The datasets' copy of the same frames: what their JPEG (4:2:0) alone moves. Information, not
# the target (`--reference dataset` labels its columns so and prints no targets).
"$tlvlink" score "${truths[@]}" "${lives[@]}" "${datasets[@]}" --reference dataset \
  | sed -n '/^live vs the datasets/,$p' >"$out/live_vs_dataset.txt"
echo
grep -E '^[a-z_]+ +frames |^grasp ' "$out/live_vs_dataset.txt" | sed 's/^/dataset copy: /'
"$tlvlink" score "${truths[@]}" "${lives[@]}" "${datasets[@]}" --reference dataset --json >"$out/live_vs_dataset.json"
echo "live_vs_offline: $(( $(date +%s) - t0 )) s; $out/live_vs_offline.txt and .json, $out/live_vs_dataset.txt and .json"
