#!/usr/bin/env bash
# Reproduces the shipped default models, firmware/models/touch-tiny-{fp32,int8}.tlvm:
#   tools/setup/make_default_models.sh [--install] [OUT_DIR]      (OUT_DIR: /tmp/tlvlink-default)
# 1. tools/trainer/train_default.sh: simulator set (12,000 Touch100k-format samples, seed 1, 64
#    simulated sensor instances),
#    TLV-Link training of `tiny` (built-in teacher, curriculum), export to OUT_DIR/tiny.tlvm.
# 2. A simulated Feel set (150 objects x 8 grasps, seed 2027, 64 sensor instances) for the grasp head.
# 3. `tlvlink heads fit`: linear probes (material, hard/soft, rough/smooth) on the training split
#    of the Touch100k set and the grasp head on the Feel set, on the runtime's own embeddings
#    -> OUT_DIR/touch-tiny-fp32.tlvm.
# 4. `tlvlink quantize` (percentile 99.99, 200 calibration frames of the training split; the
#    first convolution and the embedding layer kept in fp32: embedding cosine 0.998 instead of
#    0.993; bias correction (the default) on 64 of them: 0.9983, see quantize/README.md) -> OUT_DIR/touch-tiny-int8.tlvm, report in
#    OUT_DIR/quantize-report/.
# 5. `tlvlink eval` fp32 vs int8 on the test splits -> OUT_DIR/eval.txt.
# --install copies both models into firmware/models/. Deterministic: torch runs single-threaded
# with fixed seeds, the probes use deterministic L-BFGS, calibration picks frames by seed.
# Needs a host build with the trainer: cmake --preset host && cmake --build --preset host
set -euo pipefail
cd "$(dirname "$0")/../.."
install=0
if [ "${1:-}" = "--install" ]; then install=1; shift; fi
out=${1:-/tmp/tlvlink-default}
build=${TLVLINK_BUILD:-build/host}
tlvlink=$build/tools/cli/tlvlink

TLVLINK_BUILD=$build TLVLINK_TRAIN_ARCH=tiny bash tools/trainer/train_default.sh "$out"

feel=$out/feel
if [ ! -f "$feel/tlvlink_sim.json" ] || ! grep -q '"sensor_instances": *64' "$feel/tlvlink_sim.json"; then
  rm -rf "$feel"
  echo "== Feel set (grasp head): 150 objects x 8 grasps, 64 sensor instances, seed 2027 -> $feel"
  "$tlvlink" sim feel -o "$feel" --objects 150 --grasps-per-object 8 --repacked --seed 2027 \
    --sensor-instances 64 --vision-height 60 --vision-width 80
fi

echo "== heads fit -> $out/touch-tiny-fp32.tlvm"
"$tlvlink" heads fit "$out/tiny.tlvm" --touch "$out/data" --grasp "$feel" -q \
  -o "$out/touch-tiny-fp32.tlvm"

echo "== quantize -> $out/touch-tiny-int8.tlvm"
"$tlvlink" quantize "$out/touch-tiny-fp32.tlvm" --calib "$out/data" --calib-split train \
  --keep-float first,last -o "$out/touch-tiny-int8.tlvm" --report "$out/quantize-report" -q

echo "== eval fp32 vs int8 -> $out/eval.txt"
"$tlvlink" eval "$out/touch-tiny-fp32.tlvm" --compare "$out/touch-tiny-int8.tlvm" \
  --touch "$out/data" --grasp "$feel" -q | tee "$out/eval.txt"

if [ $install -eq 1 ]; then
  mkdir -p firmware/models
  cp "$out/touch-tiny-fp32.tlvm" "$out/touch-tiny-int8.tlvm" firmware/models/
  echo "installed into firmware/models/"
fi
sha256sum "$out/touch-tiny-fp32.tlvm" "$out/touch-tiny-int8.tlvm"
