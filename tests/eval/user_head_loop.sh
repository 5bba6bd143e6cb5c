#!/usr/bin/env bash
# The user's loop end to end (issue 30), on real GelSight Mini frames: frames saved by the
# sensor's SDK, labelled by folder -> `tlvlink heads fit --images` -> `verify` -> `sign` ->
# a running tlvlinkd (signed models required) swaps to the new model on SIGHUP and reports the
# new head. Skipped (exit 77) where the real frames are absent.
#   user_head_loop.sh TLVLINK TLVLINKD REAL_FRAMES_DIR MODEL
set -euo pipefail
tlvlink=$1 tlvlinkd=$2 real=$3 model=$4
billets=$real/gelsight-contrastive-learning
[ -d "$billets" ] || { echo "SKIP: $billets absent: the real frames are not here"; exit 77; }
work=$(mktemp -d)
daemon=
cleanup() { [ -n "$daemon" ] && kill -KILL "$daemon" 2> /dev/null; rm -rf "$work"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; [ -f "$work/daemon.log" ] && tail -n 20 "$work/daemon.log"; exit 1; }

# 1. Frames as a user keeps them: one folder per class, one subfolder per object (billet).
for b in 1 2 3; do
  mkdir -p "$work/frames/rough/billet$b" "$work/frames/smooth/billet$b" "$work/stream"
  for f in "$billets"/billet_captures/billet${b}_camera_*.png; do
    ln -s "$f" "$work/frames/rough/billet$b/"
    ln -s "$f" "$work/stream/rough_$(basename "$f")"
  done
  for f in "$billets"/billet_captures_grinded/billet${b}_camera_*.png; do
    ln -s "$f" "$work/frames/smooth/billet$b/"
    ln -s "$f" "$work/stream/smooth_$(basename "$f")"
  done
done

# 2. The live sensor's stream for the daemon: the same frames as a camera recording.
"$tlvlink" record --images "$work/stream" --hold 3 -o "$work/live.tlvraw" > /dev/null

# 3. Fit, verify, sign.
"$tlvlink" heads fit "$model" --images "$work/frames" --head roughness -o "$work/mine.tlvm" \
  > "$work/fit.txt" || fail "heads fit: $(cat "$work/fit.txt")"
grep -q "head 'roughness' (added) trusted" "$work/fit.txt" || fail "fit: $(cat "$work/fit.txt")"
"$tlvlink" verify "$work/mine.tlvm" > /dev/null || fail "verify of the fitted model"
"$tlvlink" keygen -o "$work/key" > /dev/null
"$tlvlink" sign "$model" --key "$work/key.key" -o "$work/shipped.signed.tlvm" > /dev/null
"$tlvlink" sign "$work/mine.tlvm" --key "$work/key.key" -o "$work/mine.signed.tlvm" > /dev/null
"$tlvlink" verify "$work/mine.signed.tlvm" --public-key "$work/key.pub" > /dev/null ||
  fail "verify --public-key of the signed model"

# 4. The daemon on the shipped model, then SIGHUP after the model file is replaced.
cp "$work/shipped.signed.tlvm" "$work/current.tlvm"
cat > "$work/tlvlinkd.toml" << EOF
model = "$work/current.tlvm"
model_public_key = "$work/key.pub"
output = "jsonl:$work/out.jsonl"
status_interval_ms = 60000
[contact]
enabled = false           # every frame of these captures is a press: nothing to calibrate on
[grasp]
mode = "off"
[[sensor]]
name = "finger"
model = "gelsight-mini-processed"
finger = "none"
source = "replay"
device = "$work/live.tlvraw"
loop = true
EOF
"$tlvlinkd" --config "$work/tlvlinkd.toml" 2> "$work/daemon.log" &
daemon=$!
wait_for() {  # PATTERN FILE: up to 20 s
  for _ in $(seq 200); do grep -q "$1" "$2" 2> /dev/null && return 0; sleep 0.1; done
  return 1
}
wait_for '"type":"frame_prediction"' "$work/out.jsonl" || fail "no frame predictions from the shipped model"
grep -q '"roughness"' "$work/out.jsonl" && fail "the shipped model reports a roughness head"
mv "$work/mine.signed.tlvm" "$work/current.tlvm"
kill -HUP "$daemon"
# A frame's head entry (the reloaded session's hello line names the head too: not enough).
wait_for '"name":"roughness","probabilities"' "$work/out.jsonl" || fail "no roughness predictions after SIGHUP"
grep -q "head roughness (probe): reported; trusted" "$work/daemon.log" ||
  fail "the daemon did not report the new head's trust"
kill -TERM "$daemon"
rc=0; wait "$daemon" || rc=$?
daemon=
[ "$rc" = 0 ] || fail "tlvlinkd exit $rc"
# The new head answers on the billets it was fitted on (the cross-validated figure is in fit.txt).
right=$(grep -o '"name":"roughness","probabilities":\[[^]]*\],"top_label":"[a-z]*"' "$work/out.jsonl" | wc -l)
[ "$right" -gt 0 ] || fail "no roughness answers"
echo "loop ok: fitted ($(grep -o 'head (embeddings) *accuracy *[0-9.]* %' "$work/fit.txt" | tr -s ' ')), signed, reloaded on SIGHUP, $right roughness predictions"
