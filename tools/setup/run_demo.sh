# The README's main command: sets up a fresh Debian 12 machine and runs the main job on the
# embedded default, printing what it did.
#   tools/setup/run_demo.sh
# The embedded default is the shipped touch encoder (firmware/models/touch-tiny-{fp32,int8}.tlvm:
# TLV-Link-trained on simulator data, int8 by `tlvlink quantize`; tools/setup/make_default_models.sh
# reproduces both). Frames come from the simulated GelSight Mini (tools/sim) as JPEG, like the
# camera's, and go through the real runtime: preprocessing, the XNNPACK executor (checked against
# the reference executor) and the model's heads. Outputs go to build/demo/out/.
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

step "2/7 build the runtime and the tlvlink CLI into $build (no tests)"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTLVLINK_BUILD_TESTS=OFF \
  -DTLVLINK_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target tlvlink >"$build/build.log" 2>&1 ||
  { tail -40 "$build/build.log"; echo "run_demo: build failed (full log: $build/build.log)" >&2; exit 1; }
tail -1 "$build/build.log"
tlvlink=$build/tools/cli/tlvlink
mkdir -p "$out"

step "3/7 the shipped models: inspect the int8 one (totals), verify the golden pairs stored in both"
"$tlvlink" inspect "$int8" | grep -iE "^(model|input|embedding|total|producer|checksum|heads)" || true
for m in "$fp32" "$int8"; do
  for e in xnnpack reference; do
    printf '%s on %-9s: ' "$(basename "$m")" "$e"
    "$tlvlink" verify "$m" --executor "$e" | tail -1
  done
done

step "4/7 simulated GelSight Mini: press two objects, run each frame through the int8 model"
# A hard, rough object (stone-like: 70 GPa, 150 um RMS texture) and a soft, smooth one
# (rubber-like: 100 kPa, 0.5 um). One frame cannot say whether a grasp will hold, so the grasp
# head is skipped here and scored over episodes in step 6.
"$tlvlink" sim frame -o "$out/hard_rough.jpg" --modulus 7e10 --sq-um 150 --correlation-length 1 \
  --force 8 --radius 8 --seed 11
"$tlvlink" sim frame -o "$out/soft_smooth.jpg" --modulus 1e5 --sq-um 0.5 --force 8 --radius 8 --seed 12
for name in hard_rough soft_smooth; do
  echo "-- $name.jpg (truth: ${name/_/, })"
  "$tlvlink" infer "$int8" --input "$out/$name.jpg" --threads 1 | grep -E "^head|invoke" | sed 's/^/   /'
done

step "5/7 XNNPACK against the reference executor on the same frame (the tolerances tlvlink verify uses)"
"$tlvlink" infer "$int8" --input "$out/hard_rough.jpg" -o "$out/hard_rough.npy" --compare-executors |
  grep -E "^output|LSB" | sed 's/^/   /'

step "6/7 accuracy on unseen simulated data: fp32 vs int8 (heads fitted on the training split)"
# A fresh set (new seed: new objects and sessions) in both formats the heads read.
rm -rf "$out/touch" "$out/feel"
"$tlvlink" sim touch100k -o "$out/touch" --sessions 150 --frames-per-session 4 --seed 4242 \
  --threads 2 >/dev/null
"$tlvlink" sim feel -o "$out/feel" --objects 40 --grasps-per-object 6 --repacked --seed 4243 \
  --vision-height 60 --vision-width 80 >/dev/null
"$tlvlink" eval "$fp32" --compare "$int8" --touch "$out/touch" --grasp "$out/feel" -q --no-paper \
  --oracle-samples 0 | sed 's/^/   /'

step "7/7 benchmark (XNNPACK, 300 runs, medians): fp32 vs int8, 1 and 2 threads"
for m in "$fp32" "$int8"; do
  for t in 1 2; do
    "$tlvlink" bench "$m" --threads $t --runs 300 | grep -iE "median|rss" |
      sed "s/^/   [$(basename "$m" .tlvm), $t thread(s)] /"
  done
done

echo
echo "run_demo: done. Frames and outputs are in $out/."
echo "The model is trained on simulated frames only: read its accuracies in step 6 as what the"
echo "simulator supports (firmware/models/README.md), not as real-sensor performance."
