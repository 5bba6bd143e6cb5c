#!/usr/bin/env bash
# The README's main command: sets up a fresh Debian 12 machine and runs the main job on the
# embedded default, printing what it did.
#   tools/setup/run_demo.sh
# The main job is the board's pipeline, run on this host: tlvlinkd (firmware/tlvlinkd) with two
# simulated GelSight Mini fingers on a gripper, streaming what the camera streams (MJPEG
# 3280x2464 at 25 fps, replayed at that pace from a scenario the simulator records once) through
# scripted grasps and presses: decode, contact gating, preprocessing, the shipped int8 encoder on
# XNNPACK, the heads and one grasp prediction per grasp, with a live status line, a summary
# (frames, drops, latency per stage, CPU, RSS) and the live predictions scored against the
# simulator's ground truth. The daemon also streams its predictions (runtime/protocol) to a pty,
# as it would to a UART or USB, read live by `tlvlink listen` in the background (JSON lines and
# a recording); the listener's link statistics (frames, rejected frames by cause, sequence gaps,
# added latency send -> received) close the step. The embedded default is the shipped touch encoder
# (firmware/models/touch-tiny-{fp32,int8}.tlvm: TLV-Link-trained on simulator data, int8 by
# `tlvlink quantize`; tools/setup/make_default_models.sh reproduces both). Outputs go to
# build/demo/out/.
# Environment: TLVLINK_JOBS (build jobs, default nproc).
set -euo pipefail
cd "$(dirname "$0")/../.."
jobs=${TLVLINK_JOBS:-$(nproc)}
build=build/demo
out=$build/out
models=firmware/models
fp32=$models/touch-tiny-fp32.tlvm
int8=$models/touch-tiny-int8.tlvm

step() { echo; echo "== $*"; }

step "1/7 Debian packages (tools/setup/install_deps.sh core)"
bash tools/setup/install_deps.sh core

step "2/7 build tlvlinkd and the tlvlink CLI into $build (no tests)"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTLVLINK_BUILD_TESTS=OFF \
  -DTLVLINK_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target tlvlink tlvlinkd >"$build/build.log" 2>&1 ||
  { tail -40 "$build/build.log"; echo "run_demo: build failed (full log: $build/build.log)" >&2; exit 1; }
tail -1 "$build/build.log"
tlvlink=$build/tools/cli/tlvlink
tlvlinkd=$build/firmware/tlvlinkd/tlvlinkd
mkdir -p "$out"

step "3/7 the shipped models: inspect the int8 one (totals), verify the golden pairs stored in both"
"$tlvlink" inspect "$int8" | grep -iE "^(model|input|embedding|total|producer|checksum|heads)" || true
for m in "$fp32" "$int8"; do
  for e in xnnpack reference; do
    printf '%s on %-9s: ' "$(basename "$m")" "$e"
    "$tlvlink" verify "$m" --executor "$e" | tail -1
  done
done

step "4/7 record the scenario: two simulated Minis, 6 grasps + 4 presses (tlvlink sim scenario)"
# Rendered once (~15-30 s; ~320 MB in build/demo/out/scenario: the cameras' MJPEG and the
# processed frames, exact and as JPEG), reused while its options are unchanged.
scenario=$out/scenario
# --offline: the processed frames of the view too, exactly (RGB24) and as the datasets store them
# (JPEG q90), for the live-vs-offline line of step 7; commands.txt holds the gripper controller's
# marks.
scenario_args=(--sensor gelsight-mini --grasps 6 --presses 4 --seed 2026 --offline)
if [ ! -f "$scenario/truth.jsonl" ] || [ ! -f "$scenario/A.dataset.tlvraw" ] || [ ! -f "$scenario/commands.txt" ] || [ "$(cat "$scenario/args" 2>/dev/null)" != "${scenario_args[*]}" ]; then
  "$tlvlink" sim scenario -o "$scenario" --overwrite "${scenario_args[@]}"
  echo "${scenario_args[*]}" >"$scenario/args"
else
  echo "   reusing $scenario (${scenario_args[*]})"
fi

step "5/7 tlvlinkd: both fingers live at 25 fps through the int8 model (status line, then summary)"
# The stream goes to a pty (the daemon creates it and points $out/stream-tty at its slave) that
# `tlvlink listen` reads, started first: it waits for the link and reconnects by itself.
stream_tty=$PWD/$out/stream-tty
rm -f "$out/stream.jsonl" "$out/stream.tlvrec" "$out/listen.log"
"$tlvlink" listen --serial "$stream_tty" --json --record "$out/stream.tlvrec" >"$out/stream.jsonl" 2>"$out/listen.log" &
listener=$!
trap 'kill "$listener" 2>/dev/null || true' EXIT
cat >"$out/tlvlinkd.toml" <<TOML
# Written by tools/setup/run_demo.sh: firmware/tlvlinkd/tlvlinkd.toml explains every key.
model = "$PWD/$int8"
output = ["jsonl:$PWD/$out/predictions.jsonl", "pty:$stream_tty"]
status_line = true
# The gripper controller's closed / lifting marks, logged with the scenario: every grasp is
# predicted, also one whose contact the gate cannot see (a smooth flat face filling the gel).
command_script = "$PWD/$scenario/commands.txt"
[grasp]
mode = "commanded"
[[sensor]]
name = "left"
model = "gelsight-mini"
finger = "A"
source = "replay"
device = "$PWD/$scenario/A.tlvraw"
[[sensor]]
name = "right"
model = "gelsight-mini"
finger = "B"
source = "replay"
device = "$PWD/$scenario/B.tlvraw"
TOML
# Beside it, the same scenes from their processed frames, exactly (the offline image path), into
# offline.jsonl only: step 7 compares the two on the same frames.
sed -e "s|^output = .*|output = [\"jsonl:$PWD/$out/offline.jsonl\"]|" -e '/^status_line/d' \
    -e "s|/A.tlvraw\"|/A.offline.tlvraw\"\nformat = \"rgb24\"\nwidth = 320\nheight = 240\ncrop = 0.0\njpeg_scale = 1|" \
    -e "s|/B.tlvraw\"|/B.offline.tlvraw\"\nformat = \"rgb24\"\nwidth = 320\nheight = 240\ncrop = 0.0\njpeg_scale = 1|" \
    "$out/tlvlinkd.toml" >"$out/offline.toml"
rm -f "$out/predictions.jsonl" "$out/offline.jsonl"
"$tlvlinkd" --config "$out/offline.toml" 2>"$out/offline.log" >/dev/null &
offline_daemon=$!
"$tlvlinkd" --config "$out/tlvlinkd.toml"
wait "$offline_daemon" || { tail -5 "$out/offline.log"; echo "run_demo: the offline run failed" >&2; exit 1; }
echo "   predictions: $out/predictions.jsonl ($(wc -l <"$out/predictions.jsonl") JSON lines;"
echo "   schema in firmware/tlvlinkd/README.md)"

step "6/7 the stream as the robot received it: tlvlink listen on the daemon's pty"
# The daemon drained the pty to the listener before it closed; the listener then waits for a
# link that is not coming back: stop it (it prints its statistics on SIGTERM).
sleep 0.5
kill -TERM "$listener" 2>/dev/null || true
wait "$listener" || true
trap - EXIT
count() { grep -c "\"type\":\"$1\"" "$out/stream.jsonl" || true; }
echo "   received: $(count hello) hello, $(count frame_prediction) frame predictions, $(count grasp_prediction) grasp"
echo "   predictions, $(count stats) stats; the daemon wrote $(grep -c '"type":"frame_prediction"' "$out/predictions.jsonl" || true) to its JSON lines (the same form)"
echo "   link statistics (tlvlink listen; send -> received on this machine's one clock):"
sed -n '/^link:/,$p' "$out/listen.log" | sed 's/^/     /'
echo "   stream: $out/stream.jsonl (JSON lines), $out/stream.tlvrec (tlvlink replay $out/stream.tlvrec)"
# The same run as an MCAP file for Foxglove (tools/foxglove): converted from the recording, so
# it holds exactly what the listener received.
if "$tlvlink" replay "$out/stream.tlvrec" --overwrite --record "$out/stream.mcap" >/dev/null 2>"$out/mcap.log"; then
  echo "   Foxglove: $out/stream.mcap (open it in Foxglove, or serve it live:"
  echo "     $tlvlink replay $out/stream.mcap --realtime --foxglove :8765  -> ws://127.0.0.1:8765)"
else
  echo "   Foxglove: the MCAP file could not be written: $(tail -1 "$out/mcap.log")"
fi

step "7/7 the live predictions against the simulator's ground truth, and against the offline path (tlvlink score)"
# Ten events are ten answers: read the intervals. live vs offline pairs the same frames through
# both image paths; tools/eval/live_vs_offline.sh measures it on 240 events.
"$tlvlink" score --truth "$scenario/truth.jsonl" --predictions "$out/predictions.jsonl" \
  --offline "$out/offline.jsonl" --fingers left,right | sed 's/^/   /'

echo
echo "run_demo: done. Outputs are in $out/."
echo "The model is trained on simulated frames only: read its accuracies as what the simulator"
echo "supports (firmware/models/README.md), not as real-sensor performance. The same daemon runs"
echo "on a board with cameras: firmware/tlvlinkd/README.md."
