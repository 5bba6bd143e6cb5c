#!/usr/bin/env bash
# The README's main command: sets up a fresh Debian 12 machine and runs the main job on the
# embedded default, printing what it did.
#   tools/setup/run_demo.sh
# Until the trained default model ships, the default is the generated reference encoder
# (MobileNetV2-like, seeded random weights, 128x128 input) run over generated 240x320 tactile
# frames through the real runtime: preprocessing, the XNNPACK executor and the reference executor.
# Outputs go to build/demo/out/. Environment: TLVLINK_JOBS (build jobs, default nproc).
set -euo pipefail
cd "$(dirname "$0")/../.."
jobs=${TLVLINK_JOBS:-$(nproc)}
build=build/demo
out=$build/out

step() { echo; echo "== $*"; }

step "1/7 Debian packages (tools/setup/install_deps.sh core)"
bash tools/setup/install_deps.sh core

step "2/7 build the runtime and the tlvlink CLI into $build (no tests)"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTLVLINK_BUILD_TESTS=OFF \
  -DTLVLINK_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target tlvlink >"$build/build.log" 2>&1 ||
  { tail -40 "$build/build.log"; echo "run_demo: build failed (full log: $build/build.log)" >&2; exit 1; }
tail -1 "$build/build.log"
tlvlink=$build/tools/cli/tlvlink
mkdir -p "$out"

step "3/7 generate the reference encoder, fp32 and int8 (seed 1, 128x128 input)"
"$tlvlink" gen-reference -o "$out/encoder_fp32.tlvm" --dtype fp32 --seed 1
"$tlvlink" gen-reference -o "$out/encoder_int8.tlvm" --dtype int8 --seed 1

step "4/7 inspect the int8 model (totals)"
"$tlvlink" inspect "$out/encoder_int8.tlvm" | grep -iE "^(model|input|embedding|total|producer|checksum)" || true

step "5/7 verify the golden input/output pairs embedded in each model, on both executors"
for m in fp32 int8; do
  for e in xnnpack reference; do
    printf '%s on %-9s: ' "$m" "$e"
    "$tlvlink" verify "$out/encoder_$m.tlvm" --executor "$e" | tail -1
  done
done

step "6/7 generate 4 tactile frames (240x320, the GelSight Mini processed size) and run them"
"$tlvlink" gen-frames -o "$out/frames" -n 4 --seed 100
for f in "$out"/frames/frame_*.ppm; do
  name=$(basename "$f" .ppm)
  echo "-- $name: int8 model, XNNPACK executor"
  "$tlvlink" infer "$out/encoder_int8.tlvm" --input "$f" --threads 2 | sed 's/^/   /'
  # The reference executor is the oracle: int8 outputs agree within 1 LSB (half-way cases may
  # round differently), the tolerance `tlvlink verify` uses.
  "$tlvlink" infer "$out/encoder_int8.tlvm" --input "$f" -o "$out/$name.npy" --compare-executors |
    grep -E "^output" | sed 's/^/   /'
done

step "7/7 benchmark (XNNPACK, 2 threads, 200 runs; medians)"
for m in fp32 int8; do
  "$tlvlink" bench "$out/encoder_$m.tlvm" --threads 2 --runs 200 | grep -iE "model|median|GMAC|init|first|rss" | sed "s/^/   [$m] /"
done

echo
echo "run_demo: done. Models, frames and outputs are in $out/."
echo "The reference encoder has random weights: its head predictions are meaningless; it exercises the real runtime."
