#!/usr/bin/env bash
# The press head (hard/soft from a press's peak and its change from the first frame in contact;
# tools/eval/README.md "Press head") fitted for MODEL: four scenarios of 150 single-finger presses
# (GelSight Mini 401 with markers and 402 without, DIGIT 403 with and 404 without, each on its own
# simulated sensor instances) played by tlvlinkd twice, from the cameras' raw output through the
# board's decoder (the live path) and from the exact processed frames, every frame (as fast as the
# daemon takes them) with every encoded frame's embedding reported, then `tlvlink heads fit MODEL
# --presses ...` on both plays of every press (validated by leaving each scenario out, both its
# plays). Deterministic: the same model and scenarios give the same head, byte for byte.
#   tools/eval/fit_press_head.sh WORK MODEL OUT_MODEL
#   tools/eval/fit_press_head.sh WORK --render-only   (the scenarios alone, e.g. while a model trains)
# WORK keeps the rendered scenarios (~12 GB) and the plays (reused when MODEL is the same file).
# Environment: TLVLINK_BUILD (default build/host), TLVLINK_PLAYS (plays at once, default 2). About
# 3-4 minutes on 2 cores with the scenarios rendered (~12 more to render them, one after another):
# the GelSight Mini's live path decodes ~100 frames/s of 8 MP MJPEG on a core.
set -euo pipefail
cd "$(dirname "$0")/../.."
usage="usage: fit_press_head.sh WORK MODEL OUT_MODEL | WORK --render-only"
[ $# -eq 3 ] || { [ $# -eq 2 ] && [ "$2" = --render-only ]; } ||
  { echo "fit_press_head: $usage" >&2; exit 2; }
work=$1
train=(gelsight-mini:401:150:markers gelsight-mini:402:150 digit:403:150:markers digit:404:150)
# shellcheck source=tools/eval/press_scenarios.sh
. tools/eval/press_scenarios.sh
press_tools "${TLVLINK_BUILD:-build/host}"
mkdir -p "$work"
work=$(realpath "$work")
t0=$(date +%s)
for spec in "${train[@]}"; do press_render "$work" "$spec"; done
[ "$2" = --render-only ] && exit 0
model=$2 out_model=$3
[ -f "$model" ] || { echo "fit_press_head: model $model missing" >&2; exit 2; }
model=$(realpath "$model")
echo "== tlvlinkd: ${#train[@]} press scenarios, live path and exact frames, with $model"
press_play_all "$work" "$model" live press-live "${train[@]}"
press_play_all "$work" "$model" offline press-offline "${train[@]}"
dirs=()
for spec in "${train[@]}"; do dirs+=("$(press_dir "$work" "$spec")"); done
"$tlvlink" heads fit "$model" --presses "$(IFS=,; echo "${dirs[*]}")" \
  --press-predictions press-live.jsonl,press-offline.jsonl -o "$out_model"
echo "fit_press_head: $(( $(date +%s) - t0 )) s"
