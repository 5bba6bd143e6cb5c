#!/usr/bin/env bash
# Reproduces the shipped default models, firmware/models/touch-tiny-{fp32,int8}.tlvm:
#   tools/setup/make_default_models.sh [--install] [--encoder MODEL] [OUT_DIR]
#   (OUT_DIR: /tmp/tlvlink-default; --encoder: skip step 1's training and take the encoder, and
#   the zero-shot heads, from MODEL, e.g. firmware/models/touch-tiny-fp32.tlvm to re-make only
#   the heads; the simulator set of step 1 is still made, for calibration and eval)
# 1. tools/trainer/train_default.sh: simulator set (18,000 Touch100k-format samples of 9000
#    objects, seed 1, GelSight Mini and DIGIT, 64 simulated sensor instances, half on marked
#    gels), TLV-Link training of `tiny` (built-in teacher, curriculum) with the supervised term
#    beside it (tools/trainer/README.md "Objectives"), export to OUT_DIR/tiny.tlvm.
# 2. The heads' own sets, never seen by the encoder: a touch set (3000 objects x 2 frames,
#    seed 3, same mix) and a simulated Feel set (2400 objects x 4 grasps, seed 2027, 64 sensor
#    instances, each object on a GelSight Mini or a DIGIT gripper, half of them on marked gels,
#    and half of the objects' frames through the sensor's live path (the raw camera output and
#    the board's decoder, what tlvlinkd reads) instead of the dataset's JPEG round trip: one
#    grasp head for both sensor types, gels with and without markers, and both image paths).
# 3. `tlvlink heads fit`: linear probes (material, hard/soft, rough/smooth) on the training split
#    of the heads' touch set and the grasp head on the Feel set, on the runtime's own embeddings
#    and each finger's before-to-during difference statistics (runtime/heads/README.md);
#    each head records its test accuracy (trust) -> OUT_DIR/touch-tiny-fp32.tlvm. Zero-shot heads
#    that do not beat the majority class are left out. Then the two-class touch heads are
#    fitted again (`--only`), each with second views of its training frames and the view
#    penalty (its answer must not move between a frame and its re-encoding): hard/soft on each
#    training frame also saved as JPEG q75 and q90 (weight 5); rough/smooth on those, on each
#    frame through its sensor's live path (`--train-live`), and on the Feel set's training
#    grasps (each finger's frame during the grasp, labelled with the object's material:
#    `--touch-from-grasps`), weight 5: with the JPEG views alone it lost 10-14 points on the
#    gripper scenarios of the GelSight Mini. The material head keeps its plain fit: it pays too
#    much accuracy for the penalty, and the JPEG rows alone do not steady it
#    (firmware/models/README.md "Stability").
# 4. `tlvlink quantize` (percentile 99.99, 200 calibration frames of the training split; the
#    first convolution and the embedding layer kept in fp32; bias correction on 64 of them,
#    quantize/README.md), the grasp heads fitted again (step 3's recipe) on the int8 file's own
#    embeddings, what the board computes; then `tlvlink eval --record` re-measures the int8
#    heads on the same test splits -> OUT_DIR/touch-tiny-int8.tlvm, report in
#    OUT_DIR/quantize-report/.
# 5. The press head (hard/soft from how a press's imprint changes: its peak and the peak minus its
#    first frame in contact) of each file, fitted on its own embeddings by
#    tools/eval/fit_press_head.sh: four scenarios of 150 single-finger presses (GelSight Mini and
#    DIGIT, seeds 401-404, in OUT_DIR/presses) played by tlvlinkd, every frame, from the cameras'
#    raw output and from the exact frames (the scenarios rendered beside steps 1-4); validated by
#    leaving each scenario out.
# Steps 2 and 5's sets are made beside step 1, at a lower priority (logs: OUT_DIR/head-sets.log,
# OUT_DIR/presses-render.log).
# 6. `tlvlink eval` fp32 vs int8 on the encoder set's and the Feel set's test splits
#    -> OUT_DIR/eval.txt.
# Every file written carries the integrity trailer and its golden head outputs (the writers
# seal what they write: runtime/README.md "Integrity trailer").
# --install copies both models into firmware/models/. Deterministic: torch runs single-threaded
# with fixed seeds, the probes use deterministic L-BFGS, calibration picks frames by seed.
# The heads fits and evals embed two frames at a time and fit the heads' probes side by side
# (--threads 2; the outputs are the same on one). About 57 min on 2 cores from nothing
# (firmware/models/README.md "How they were made").
# Needs a host build with the trainer (cmake --preset host && cmake --build --preset host) and
# ~15 GB free in OUT_DIR (checked first; TLVLINK_MODELS_NEED_GB changes the figure).
set -euo pipefail
cd "$(dirname "$0")/../.."
install=0
encoder=""
while [ $# -gt 0 ]; do
  case "$1" in
    --install) install=1; shift ;;
    --encoder) encoder=$2; shift 2 ;;
    *) break ;;
  esac
done
out=${1:-/tmp/tlvlink-default}
build=${TLVLINK_BUILD:-build/host}
tlvlink=$build/tools/cli/tlvlink
t0=$(date +%s)
mkdir -p "$out"
# The sets and press scenarios take ~14 GB (the scenarios 12): refuse to start without the room
# rather than fail at step 5 a quarter of an hour in (what OUT already holds is reused).
need_gb=${TLVLINK_MODELS_NEED_GB:-15}
have_kb=$(du -sk "$out" | cut -f1)
free_kb=$(df -Pk "$out" | awk 'NR == 2 {print $4}')
if [ $((free_kb + have_kb)) -lt $((need_gb * 1024 * 1024)) ]; then
  echo "make_default_models: $out has $((free_kb / 1048576)) GB free and holds" \
       "$((have_kb / 1048576)) GB; the sets and press scenarios need ~$need_gb GB" >&2
  exit 1
fi
# A set's tlvlink_sim.json holds every generator option: reuse the set when they match.
generated() {  # dir key=value...
  local dir=$1; shift
  [ -f "$dir/tlvlink_sim.json" ] || return 1
  for kv in "$@"; do grep -Eq "\"${kv%%=*}\": *${kv#*=}(,|$)" "$dir/tlvlink_sim.json" || return 1; done
}
heads=$out/heads-touch
feel=$out/feel
# Step 2's sets (the simulator's output is the same for any thread count).
make_head_sets() {
  if ! generated "$heads" sessions=3000 frames_per_session=2 seed=3 sensor_instances=64 \
      'sensor="gelsight-mini,digit"' markers_fraction=0.5; then
    rm -rf "$heads"
    echo "== heads' touch set: 3000 sessions x 2 frames, seed 3 -> $heads"
    "$tlvlink" sim touch100k -o "$heads" --sessions 3000 --frames-per-session 2 --seed 3 \
      --sensor gelsight-mini,digit --sensor-instances 64 --markers-fraction 0.5 --threads 2 \
      --vision-height 24 --vision-width 32
  fi
  if ! generated "$feel" objects=2400 grasps_per_object=4 seed=2027 sensor_instances=64 \
      'sensor="gelsight-mini,digit"' markers=false markers_fraction=0.5 live_path_fraction=0.5; then
    rm -rf "$feel"
    echo "== Feel set (grasp head): 2400 objects x 4 grasps (GelSight Mini and DIGIT, markers on" \
         "half, live path on half), 64 sensor instances, seed 2027 -> $feel"
    "$tlvlink" sim feel -o "$feel" --objects 2400 --grasps-per-object 4 --repacked --seed 2027 \
      --sensor gelsight-mini,digit --markers-fraction 0.5 --live-path-fraction 0.5 \
      --sensor-instances 64 --vision-height 24 --vision-width 32 --threads 2
  fi
}
# Step 5's press scenarios, then step 2's sets, are made beside step 1 (the training runs on one
# thread), at a lower priority so that the training keeps its core.
(
  renice -n 10 -p "$BASHPID" > /dev/null
  TLVLINK_BUILD=$build bash tools/eval/fit_press_head.sh "$out/presses" --render-only \
    > "$out/presses-render.log" 2>&1 ||
    { echo "press scenarios failed: $out/presses-render.log" >&2; exit 1; }
  make_head_sets > "$out/head-sets.log" 2>&1 ||
    { echo "heads' sets failed: $out/head-sets.log" >&2; exit 1; }
) &
beside=$!

if [ -n "$encoder" ]; then
  [ -f "$encoder" ] || { echo "make_default_models: --encoder $encoder: no such file" >&2; exit 2; }
  TLVLINK_BUILD=$build bash tools/trainer/train_default.sh --data-only "$out"
  cp "$encoder" "$out/tiny.tlvm"
  echo "== encoder taken from $encoder (not trained)"
else
  TLVLINK_BUILD=$build TLVLINK_TRAIN_ARCH=tiny bash tools/trainer/train_default.sh "$out"
fi

wait "$beside" || { tail -5 "$out/presses-render.log" "$out/head-sets.log" 2>/dev/null; exit 1; }

echo "== heads fit -> $out/touch-tiny-fp32.tlvm"
"$tlvlink" heads fit "$out/tiny.tlvm" --threads 2 --touch "$heads" --grasp "$feel" -q \
  --grasp-features before-during-difference --overwrite -o "$out/heads-plain.tlvm"
"$tlvlink" heads fit "$out/heads-plain.tlvm" --threads 2 --touch "$heads" -q --only hard_soft \
  --train-jpeg 75,90 --view-weight 5 --max-iterations 3000 --no-zero-shot \
  --overwrite -o "$out/heads-hard-soft.tlvm"
"$tlvlink" heads fit "$out/heads-hard-soft.tlvm" --threads 2 --touch "$heads" -q \
  --only rough_smooth --touch-from-grasps "$feel" --train-jpeg 75,90 --train-live --view-weight 5 \
  --max-iterations 3000 --no-zero-shot --overwrite -o "$out/touch-tiny-fp32.tlvm"

echo "== quantize -> $out/touch-tiny-int8.tlvm"
"$tlvlink" quantize "$out/touch-tiny-fp32.tlvm" --calib "$out/data" --calib-split train \
  --keep-float first,last -o "$out/int8-quantized.tlvm" --report "$out/quantize-report" -q
# The grasp heads read small before-to-during changes of the embeddings: fitted on the fp32
# file's, the board read live grasps worse (firmware/models/README.md "Live = offline"; why is not
# established). Fitted again on the int8 file's own embeddings, what the board computes.
"$tlvlink" heads fit "$out/int8-quantized.tlvm" --threads 2 --grasp "$feel" -q \
  --only grasp --grasp-features before-during-difference --no-zero-shot --overwrite \
  -o "$out/int8-unrecorded.tlvm"
# The board's file records the board's figures: the int8 heads re-measured on the same splits.
"$tlvlink" eval "$out/int8-unrecorded.tlvm" --threads 2 --touch "$heads" --grasp "$feel" -q \
  --no-paper --oracle-samples 0 --record "$out/touch-tiny-int8.tlvm" > /dev/null

echo "== press heads -> $out/touch-tiny-{fp32,int8}.tlvm"
for f in fp32 int8; do
  TLVLINK_BUILD=$build bash tools/eval/fit_press_head.sh "$out/presses" "$out/touch-tiny-$f.tlvm" \
    "$out/press-$f.tlvm" | grep -E '^ *(press head|baseline|majority)|^head|^fit_press_head'
  mv "$out/press-$f.tlvm" "$out/touch-tiny-$f.tlvm"
done

echo "== eval fp32 vs int8 -> $out/eval.txt"
"$tlvlink" eval "$out/touch-tiny-fp32.tlvm" --threads 2 --compare "$out/touch-tiny-int8.tlvm" \
  --touch "$out/data" --grasp "$feel" -q | tee "$out/eval.txt"

if [ $install -eq 1 ]; then
  mkdir -p firmware/models
  cp "$out/touch-tiny-fp32.tlvm" "$out/touch-tiny-int8.tlvm" firmware/models/
  echo "installed into firmware/models/"
fi
echo "make_default_models: total $(( $(date +%s) - t0 ))s"
sha256sum "$out/touch-tiny-fp32.tlvm" "$out/touch-tiny-int8.tlvm"
