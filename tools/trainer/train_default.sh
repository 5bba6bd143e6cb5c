#!/usr/bin/env bash
# Trains the default model: `tiny` with TLV-Link's default settings except the learning rate (see
# below) and with the sensor-view recipe, on a simulator set, then exports it to a float .tlvm.
#   tools/trainer/train_default.sh [--no-curriculum | --data-only] [OUT_DIR] [-- EXTRA TRAIN FLAGS]
#   (OUT_DIR: /tmp/tlvlink-default; extra flags, e.g. `-- --lr 1e-3`, go to `tlvlink train`)
# Steps: (1) generate the Touch100k-format set with a fixed seed (reused when OUT_DIR/data
# already holds it), (2) `tlvlink train` (built-in teacher pre-training, then the student),
# (3) `tlvlink export`. --no-curriculum trains the paper's ablation (beta = 0, no teacher) into
# OUT_DIR/no-curriculum/ from the same data. --data-only stops after (1) (the set is what
# calibration and eval read when an encoder is reused: make_default_models.sh --encoder). Environment: TLVLINK_BUILD (build directory,
# default build/host), TLVLINK_TRAIN_THREADS (torch threads, default 1; see README "Threads"),
# TLVLINK_TRAIN_ARCH (default tiny), TLVLINK_TRAIN_OBJECTIVE (default tlv-link+supervised;
# tlv-link for the pure method, supervised for the supervised bound: then no teacher either),
# TLVLINK_TRAIN_NAME (output name, default the arch).
# Target: under 60 min wall on the shared 2-core development machine (README "Default model").
set -euo pipefail
cd "$(dirname "$0")/../.."
variant=curriculum
data_only=0
if [ "${1:-}" = "--no-curriculum" ]; then variant=no-curriculum; shift; fi
if [ "${1:-}" = "--data-only" ]; then data_only=1; shift; fi
out=/tmp/tlvlink-default
if [ $# -gt 0 ] && [ "$1" != "--" ]; then out=$1; shift; fi
[ "${1:-}" = "--" ] && shift
extra=("$@")
# `tiny` (12.8 MMAC, 0.36 M parameters) is the shipped default (README "Default model").
arch=${TLVLINK_TRAIN_ARCH:-tiny}
objective=${TLVLINK_TRAIN_OBJECTIVE:-tlv-link+supervised}
name=${TLVLINK_TRAIN_NAME:-$arch}
# The paper's lr 2e-4 fine-tunes pre-trained CLIP encoders; a student trained from scratch
# under-trains with it (the loss rises again as beta decays), 1e-3 trains it. An --lr among the
# extra flags replaces it.
lr_flag=(--lr 1e-3)
for a in "${extra[@]}"; do [[ $a == --lr* ]] && lr_flag=(); done
build=${TLVLINK_BUILD:-build/host}
threads=${TLVLINK_TRAIN_THREADS:-1}
tlvlink=$build/tools/cli/tlvlink
if [ ! -x "$tlvlink" ] || [ ! -x "$build/tools/cli/tlvlink-train" ]; then
  echo "train_default: $tlvlink or tlvlink-train missing; build first:" >&2
  echo "  cmake --preset host && cmake --build --preset host --target tlvlink" >&2
  exit 1
fi

# The dataset: 9000 sessions x 2 frames = 18,000 samples (14,400 train / 3,600 test by
# session), seed 1. Many objects with few frames each: with 8 frames of 1500 objects a student
# learned the objects rather than their materials (tools/trainer/README.md "Default model").
# Each session is recorded on one of 64 simulated sensor instances (LED gains, background,
# white balance, exposure), on a GelSight Mini or a DIGIT (half each: one model for both sensor
# types), half of them on gels with markers. Vision images at the student's input size (the
# built-in teacher's input; larger ones would only be resized down).
sessions=9000
frames=2
instances=64
sensors=gelsight-mini,digit
markers=0.5
data=$out/data
t0=$(date +%s)
if [ -f "$data/tlvlink_sim.json" ] && grep -q "\"sessions\": *$sessions" "$data/tlvlink_sim.json" &&
   grep -q "\"frames_per_session\": *$frames" "$data/tlvlink_sim.json" &&
   grep -q "\"sensor_instances\": *$instances" "$data/tlvlink_sim.json" &&
   grep -q "\"sensor\": *\"$sensors\"" "$data/tlvlink_sim.json" &&
   grep -q "\"markers_fraction\": *$markers" "$data/tlvlink_sim.json" &&
   grep -Eq "\"seed\": *1,?$" "$data/tlvlink_sim.json"; then
  echo "== 1/3 reusing the simulator set in $data"
else
  rm -rf "$data"
  echo "== 1/3 simulator set: $sessions sessions x $frames frames ($sensors, $instances sensor" \
       "instances, markers on $markers of them), seed 1 -> $data"
  "$tlvlink" sim touch100k -o "$data" --sessions $sessions --frames-per-session $frames \
    --sensor "$sensors" --sensor-instances $instances --markers-fraction $markers --seed 1 \
    --threads 2 --vision-height 96 --vision-width 128
fi
t1=$(date +%s)
if [ $data_only -eq 1 ]; then
  echo "train_default: data only ($((t1 - t0))s) -> $data"
  exit 0
fi

dir=$out
# The sensor-view recipe (README "Sensor-view augmentation"; issue 29): the model input is the
# area average of the frame, every frame becomes two views of the same touch as other sensors
# and links show it (mounting, optics, LEDs, dust, focus, noise, codec), and the two must embed
# alike (cosine, weight 10) and answer alike (the supervised heads' symmetric KL, weight 2;
# supervised objectives only).
view_flags=(--resize area --augment-view all --consistency-weight 10)
[ "$objective" != tlv-link ] && view_flags+=(--prediction-consistency-weight 2)
flags=(--objective "$objective" "${view_flags[@]}")
if [ "$variant" = no-curriculum ]; then dir=$out/no-curriculum; flags+=(--no-curriculum); fi
mkdir -p "$dir"
echo "== 2/3 train $arch ($variant, $objective), threads $threads -> $dir/$name.ckpt"
"$tlvlink" train "$data" -o "$dir/$name.ckpt" --arch "$arch" "${lr_flag[@]}" --seed 1 \
  --threads "$threads" --checkpoint-dir "$dir/checkpoints-$name" --checkpoint-every 600 \
  "${flags[@]}" "${extra[@]}"
t2=$(date +%s)

echo "== 3/3 export -> $dir/$name.tlvm"
"$tlvlink" export "$dir/$name.ckpt" -o "$dir/$name.tlvm"
t3=$(date +%s)
echo "train_default: data $((t1 - t0))s, train $((t2 - t1))s, export $((t3 - t2))s," \
     "total $((t3 - t0))s; model $dir/$name.tlvm"
