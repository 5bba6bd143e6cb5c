#!/usr/bin/env bash
# Runs the capture tests inside the emulated arm64 board: Debian's arm64 kernel under
# qemu-system-aarch64 (virt machine, TCG) with vivid loaded (tools/rig). First the rig's own
# tests (tools/rig/test_riglib.py, tools/rig/selftest.sh: ports, share, USB gadget, vivid), then
# the capture test programs cross-built for the board presets (generic-a76 / rpi4-a72; only
# those targets, in the cross stage's build trees), one boot per CPU, with boot, test and build
# times. In the generic-a76 boot the prediction stream's USB tests follow the capture tests
# (tests/listen/rig: FunctionFS bulk <-> libusb and CDC-ACM through dummy_hcd, replug, reader
# restart, corruption injection; ~2.5 min; with --bench also the throughput benchmark over each
# link, which the test command does not run); their figures are printed at the end.
# Then the hardware-in-the-loop run (tests/hil/hil_test.sh: tlvlinkd on simulated GelSight frames
# through vivid, predictions over the USB gadget compared one by one with the host build; fault
# runs in the Cortex-A76 boot, the clean run in a Cortex-A72 boot; ~5 min).
#   board_test.sh [a76|a72|all] [--bench]        (default: all)
# Environment: TLVLINK_JOBS (build jobs, default 2: the machine is shared); PYTHON (default
# /usr/bin/python3: the rig needs only its standard library).
# Logs: build/logs/board-<preset>-{configure,build}.log; the guest's console: build/rig/<preset>/.
set -uo pipefail
cd "$(dirname "$0")/../.."

which=all bench=0
for arg in "$@"; do
  case "$arg" in
    --bench) bench=1 ;;
    *) which=$arg ;;
  esac
done
jobs=${TLVLINK_JOBS:-2}
case "$which" in
  a76) presets=(generic-a76) ;;
  a72) presets=(rpi4-a72) ;;
  all) presets=(generic-a76 rpi4-a72) ;;
  *) echo "board_test.sh: unknown target '$which' (a76|a72|all)" >&2; exit 2 ;;
esac
programs=(tests/capture/capture_vivid_test tests/capture/capture_unit_test runtime/capture/capture_probe)
# The USB stream tests run in one preset's boot only (they test the link, not the CPU).
usb_preset=generic-a76
usb_programs=(tools/listen/bench/tlvlink_stream_check)
# The hardware-in-the-loop programs (tests/hil): built with each preset, run by hil_test.sh.
hil_targets=(tlvlinkd tlvlink_hil_feeder tlvlink_hil_relay)
py=${PYTHON:-/usr/bin/python3}

now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.1f", b - a}'; }
mkdir -p build/logs

t0=$(now)
bash tools/setup/install_deps.sh rig || { echo "board_test: install_deps.sh rig failed" >&2; exit 1; }
bash tools/setup/make_sysroot.sh || { echo "board_test: make_sysroot.sh failed" >&2; exit 1; }
"$py" tools/rig/rig.py prepare >/dev/null || { echo "board_test: rig.py prepare failed" >&2; exit 1; }
echo "board_test: packages, sysroot, kernel + busybox cache $(secs "$t0" "$(now)")s"

failed=0
summary=()
t0=$(now)
if "$py" tools/rig/test_riglib.py >build/logs/board-riglib.log 2>&1 &&
   PYTHON=$py bash tools/rig/selftest.sh >build/logs/board-selftest.log 2>&1; then
  summary+=("rig self-test: $(grep -E '^rig: tests ' build/logs/board-selftest.log | tail -1 | sed 's/^rig: //') ($(secs "$t0" "$(now)")s)")
else
  # Indented: run_tests.sh counts the one "rig: tests" line printed below, not this copy of it.
  cat build/logs/board-riglib.log build/logs/board-selftest.log | tail -60 | sed 's/^/  /'
  summary+=("rig self-test: FAILED (logs: build/logs/board-riglib.log, build/logs/board-selftest.log)")
  failed=1
fi
grep -E "^rig: tests " build/logs/board-selftest.log | tail -1
for preset in "${presets[@]}"; do
  cpu=$(sed -n 's/.*"TLVLINK_QEMU_CPU": "\([^"]*\)".*/\1/p' "boards/$preset.json")
  log=build/logs/board-$preset
  t0=$(now)
  preset_programs=("${programs[@]}")
  script=tests/capture/rig/capture_rig.sh
  extra=()
  if [ "$preset" = "$usb_preset" ]; then
    preset_programs+=("${usb_programs[@]}")
    # One boot: the capture script, then the USB stream script.
    mkdir -p "build/rig/$preset"
    script=build/rig/$preset/board-test.sh
    cat tests/capture/rig/capture_rig.sh tests/listen/rig/stream_rig.sh >"$script"
    extra=(--file tests/listen/rig:/payload/stream
           --file runtime/transport/scripts/usb_gadget.sh:/payload/stream/usb_gadget.sh)
  fi
  targets=()
  for p in "${preset_programs[@]}"; do targets+=("$(basename "$p")"); done
  targets+=("${hil_targets[@]}")
  # A tree the cross stage configured is only built here (its tests may be running beside this:
  # a second configure would rewrite their files); cmake re-configures by itself when it must.
  if ! { { [ -f "build/$preset/CMakeCache.txt" ] || cmake --preset "$preset" >"$log-configure.log" 2>&1; } &&
         cmake --build --preset "$preset" -j "$jobs" --target "${targets[@]}" >"$log-build.log" 2>&1; }; then
    grep -E "error:|FAILED:|CMake Error" "$log-configure.log" "$log-build.log" | cut -c1-300 | head -30
    summary+=("$preset: BUILD FAILED (logs: $log-*.log)")
    failed=1
    continue
  fi
  t_build=$(secs "$t0" "$(now)")
  args=("${extra[@]}")
  for p in "${preset_programs[@]}"; do args+=(--program "build/$preset/$p"); done
  echo "=== $preset: rig -cpu $cpu (build ${t_build}s)"
  t0=$(now)
  "$py" tools/rig/rig.py run --cpu "$cpu" --script "$script" "${args[@]}" \
    --env TLVLINK_RIG=1 --env TLVLINK_RIG_BENCH=$bench --out "build/rig/$preset" | tee "$log-rig.log"
  rc=${PIPESTATUS[0]}
  t_rig=$(secs "$t0" "$(now)")
  line=$(grep -E "^rig: tests " "$log-rig.log" | tail -1)
  boot=$(grep -Eo "boot to init [0-9.]+s" "$log-rig.log" | tail -1)
  if [ "$rc" -eq 0 ]; then summary+=("$preset (-cpu $cpu): build ${t_build}s, rig ${t_rig}s, $boot; ${line#rig: }")
  else summary+=("$preset (-cpu $cpu): RIG FAILED in ${t_rig}s; ${line#rig: }"); failed=1; fi
done

# The USB stream's figures (printed, not asserted; the guest runs under TCG emulation).
usb_log=build/logs/board-$usb_preset-rig.log
if [[ " ${presets[*]} " == *" $usb_preset "* ]] && [ -f "$usb_log" ]; then
  echo
  echo "USB stream figures ($usb_preset boot; qemu TCG emulation, both ends in one guest: not hardware figures):"
  grep -E "^ +usb-(ffs|acm) " "$usb_log" | sed 's/^ */  /'
  grep -E "^ +board: [0-9.]+ wire bytes per frame" "$usb_log" | head -1 | sed 's/^ */  /'
  echo "  corruption injection (bytes damaged between the board's Sender and the USB link):"
  echo "  | link | byte error rate | byte drop rate | bytes damaged | predictions posted | received intact | lost | of which dropped by the board's queue | rejected (crc / cobs / truncated) | corrupted accepted |"
  echo "  |---|---|---|---|---|---|---|---|---|---|"
  grep -E "^ +corruption (ffs|acm) " "$usb_log" | sed 's/^ *corruption //' | awk '{
      for (i = 2; i <= NF; ++i) { split($i, kv, "="); v[kv[1]] = kv[2] }
      printf "  | %s | %s | %s | %s + %s of %s | %s | %s | %s | %s | %s / %s / %s | **%s** |\n", $1, v["errors"], v["drops"],
             v["corrupted"], v["dropped"], v["bytes"], v["expected"], v["received"], v["lost"], v["queue_drops"], v["crc"],
             v["cobs"], v["truncated"], v["corrupted_accepted"] }'
fi

# The hardware-in-the-loop run: its own boots (boot to first prediction is one of its figures).
echo
t0=$(now)
if PYTHON=$py bash tests/hil/hil_test.sh "$which" >build/logs/board-hil.log 2>&1; then
  summary+=("hil ($which): $(grep -c '^hil_compare: PASS' build/logs/board-hil.log) comparison(s) passed ($(secs "$t0" "$(now)")s)")
else
  tail -120 build/logs/board-hil.log
  summary+=("hil ($which): FAILED in $(secs "$t0" "$(now)")s (log: build/logs/board-hil.log; guest consoles: build/hil/<preset>/rig/)")
  failed=1
fi
echo "Hardware-in-the-loop (tests/hil; qemu TCG emulation):"
grep -E "^\| |^boot to first prediction|^host reference|^hil:|^=== hil|^HIL " build/logs/board-hil.log | sed 's/^/  /'

echo
echo "board_test summary (-j$jobs):"
printf '  %s\n' "${summary[@]}"
if [ $failed -eq 0 ]; then echo "board_test: PASS"; else echo "board_test: FAIL"; fi
exit $failed
