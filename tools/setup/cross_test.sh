#!/usr/bin/env bash
# Cross-builds the aarch64 board presets and runs their tests under qemu-aarch64 (user mode).
#   cross_test.sh [a76|a72|all] [--build-only|--test-only]        (default: all, build and test)
#     a76 -> preset generic-a76 (-mcpu/-cpu cortex-a76), a72 -> preset rpi4-a72 (cortex-a72)
#     all -> one test tree under both CPU models: the Cortex-A72 build (it runs on both) under
#            -cpu cortex-a72, then what runs differently under -cpu cortex-a76 (XNNPACK picks
#            its dot-product kernels at run time: a72_on_a76 below); the Cortex-A76 build is
#            built (the emulated board runs it:
#            board_test.sh) and runs only what depends on being compiled for the A76: its CPU
#            check (daemon.refuses_a_cpu_without_its_features / runs_on_the_cpu_it_is_built_for)
#            and the x86-64 parity of its own code (CrossArchParity).
#     --build-only / --test-only: the two halves (run_tests.sh builds first, then starts the
#            emulated board's stage beside these tests).
# Environment:
#   TLVLINK_JOBS              parallel build/test jobs (default 2: the machine is shared)
#   TLVLINK_CROSS_CMAKE_ARGS  extra configure arguments, e.g. -DTLVLINK_BUILD_HOST_TOOLS=ON
# Before the boards, records x86-64 outputs of two reference encoders and the two shipped models
# (firmware/models/) into build/parity; each
# board's cross_arch_parity_test must reproduce them (int8 bit-identical, fp32 within 1e-4).
# Prints per-step timings, a size line per board (STYLE practice 14) and a summary; exits non-zero
# if anything failed. Logs: build/logs/cross-<preset>-{configure,build,test}.log
set -uo pipefail
cd "$(dirname "$0")/../.."

which=all build=1 test=1
for a in "$@"; do
  case "$a" in
    a76|a72|all) which=$a ;;
    --build-only) test=0 ;;
    --test-only) build=0 ;;
    *) echo "cross_test.sh: unknown argument '$a' (a76|a72|all, --build-only|--test-only)" >&2; exit 2 ;;
  esac
done
jobs=${TLVLINK_JOBS:-2}
# Test runs: "preset cpu [ctest -R regex]" (no regex: the whole suite).
a76_own='^daemon\.(refuses_a_cpu_without_its_features|runs_on_the_cpu_it_is_built_for)$|^CrossArchParity\.'
# What takes another path when the same A72 binary runs on an A76: XNNPACK's kernels (cpuinfo
# finds the dot product: sdot instead of smlal), so its op, edge, random-graph and no-allocation
# suites, the shipped models' golden pairs, the x86-64 parity, the daemon's model check and its
# int8 embedding. Nothing else dispatches on the CPU model (no code of ours; libjpeg-turbo's NEON
# and glibc's string functions pick the same for both cores): it runs once, under cortex-a72.
a72_on_a76='^(Xnnpack[A-Za-z]*|CrossArchParity|ShippedModel)\.|^daemon\.verify_shipped_model$|^DaemonSession\.ReportsTheEmbeddingAndItsInt8Tensor$'
case "$which" in
  a76) presets=(generic-a76); runs=("generic-a76 cortex-a76") ;;
  a72) presets=(rpi4-a72); runs=("rpi4-a72 cortex-a72") ;;
  all) presets=(rpi4-a72 generic-a76)
       runs=("rpi4-a72 cortex-a72" "rpi4-a72 cortex-a76 $a72_on_a76" "generic-a76 cortex-a76 $a76_own") ;;
esac

now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.1f", b - a}'; }
mkdir -p build/logs

# 1. Packages (cross compiler, qemu-user) and 2. the arm64 sysroot.
t0=$(now)
bash tools/setup/install_deps.sh cross || { echo "cross_test: install_deps.sh cross failed" >&2; exit 1; }
t_install=$(secs "$t0" "$(now)")
t0=$(now)
bash tools/setup/make_sysroot.sh || { echo "cross_test: make_sysroot.sh failed" >&2; exit 1; }
t_sysroot=$(secs "$t0" "$(now)")
echo "cross_test: install_deps ${t_install}s, sysroot ${t_sysroot}s"

# 3. The x86-64 recording the boards' cross_arch_parity_test compares against: the host build
#    generates two reference encoders (int8, fp32) and records both executors' outputs.
t0=$(now)
record_parity() {
  cmake --preset host >build/logs/cross-parity-record.log 2>&1 &&
    cmake --build --preset host -j "$jobs" --target tlvlink cross_arch_parity_test \
      >>build/logs/cross-parity-record.log 2>&1 || return 1
  rm -rf build/parity && mkdir -p build/parity
  for dtype in int8 fp32; do
    build/host/tools/cli/tlvlink gen-reference -o "build/parity/encoder_$dtype.tlvm" \
      --dtype "$dtype" --seed 7 >>build/logs/cross-parity-record.log 2>&1 || return 1
  done
  # The shipped default models too: what a board actually runs (the int8 one is mixed: an int8
  # body that must be bit-identical, an fp32 embedding layer within the float tolerance).
  cp firmware/models/touch-tiny-fp32.tlvm firmware/models/touch-tiny-int8.tlvm build/parity/ || return 1
  TLVLINK_PARITY_DIR=build/parity TLVLINK_PARITY_RECORD=1 build/host/tests/parity/cross_arch_parity_test \
    >>build/logs/cross-parity-record.log 2>&1
}
if [ $build -eq 1 ] && ! record_parity; then
  tail -30 build/logs/cross-parity-record.log
  echo "cross_test: recording the x86-64 parity outputs failed (log: build/logs/cross-parity-record.log)" >&2
  exit 1
fi
[ $build -eq 0 ] || echo "cross_test: x86-64 parity recording $(secs "$t0" "$(now)")s ($(ls build/parity | wc -l) files in build/parity)"

# Text+data bytes of an ELF file or archive (what ends up in flash/RAM; debug info excluded).
elf_bytes() {
  aarch64-linux-gnu-size -t "$1" 2>/dev/null | awk 'END {print $1 + $2}'
}
human() { awk -v b="$1" 'BEGIN {if (b >= 1048576) printf "%.2f MB", b / 1048576; else printf "%.1f KB", b / 1024}'; }

# The test executables of the current configuration (ctest knows them; a stale binary left
# from an earlier configuration is not listed).
test_binaries() {  # $1 preset
  ctest --preset "$1" --show-only=json-v1 2>/dev/null | grep -o '"/[^"]*_test"' | tr -d '"' |
    sort -u | while IFS= read -r f; do [ -x "$f" ] && echo "$f"; done
}

# One line: the runtime's component libraries (each and their sum) and the test binaries. Also
# kept in build/<preset>/sizes.txt so the next run can show growth.
runtime_archives() {  # $1 preset: the component archives this configuration built
  local c
  for c in runtime/*/; do
    c=$(basename "$c")
    if [ -f "build/$1/runtime/$c/libtlvlink_$c.a" ]; then echo "build/$1/runtime/$c/libtlvlink_$c.a"; fi
  done
}
size_report() {  # $1 preset
  local dir=build/$1 line tests=() parts=() prev total=0
  while IFS= read -r a; do
    local b; b=$(elf_bytes "$a")
    total=$((total + b))
    parts+=("$(basename "$a" .a | sed 's/^libtlvlink_//') $(human "$b")")
  done < <(runtime_archives "$1")
  [ "$total" -gt 0 ] || { echo "size $1: no runtime component library built"; return; }
  line="size $1 (text+data): runtime $(human "$total") ($(printf '%s, ' "${parts[@]}" | sed 's/, $//'))"
  prev=$(awk '$1 == "runtime" {print $2}' "$dir/sizes.txt" 2>/dev/null)
  if [ -n "$prev" ] && [ "$prev" != "$total" ]; then
    line+=" ($(awk -v a="$prev" -v b="$total" 'BEGIN {printf "%+d B", b - a}') since last run)"
  fi
  echo "runtime $total" >"$dir/sizes.txt.new"
  while IFS= read -r t; do
    local b; b=$(elf_bytes "$t")
    tests+=("$(basename "$t") $(human "$b")")
    echo "$(basename "$t") $b" >>"$dir/sizes.txt.new"
  done < <(test_binaries "$1")
  mv "$dir/sizes.txt.new" "$dir/sizes.txt"
  if [ ${#tests[@]} -gt 0 ]; then
    line+="; tests: $(printf '%s, ' "${tests[@]}")"
    line=${line%, }
  fi
  echo "$line"
}

summary=()
failed=0
for preset in "${presets[@]}"; do
  [ $build -eq 1 ] || break
  log=build/logs/cross-$preset
  echo "=== $preset: configure + build (-j$jobs)"
  t0=$(now)
  # shellcheck disable=SC2086  # extra arguments are meant to split
  if ! cmake --preset "$preset" ${TLVLINK_CROSS_CMAKE_ARGS:-} >"$log-configure.log" 2>&1; then
    grep -E -A12 "CMake Error|FATAL" "$log-configure.log" | head -60
    summary+=("$preset: CONFIGURE FAILED (log: $log-configure.log)"); failed=1; continue
  fi
  # Keep going past errors: the tests that did build still run (the rest show as *_NOT_BUILT).
  if cmake --build --preset "$preset" -j "$jobs" -- -k 0 >"$log-build.log" 2>&1; then
    echo "build: $(secs "$t0" "$(now)")s"
    summary+=("$preset: build $(secs "$t0" "$(now)")s")
  else
    grep -E "error:|FAILED:|undefined reference" "$log-build.log" | cut -c1-300 | head -40
    echo "build: FAILED after $(secs "$t0" "$(now)")s (log: $log-build.log)"
    summary+=("$preset: BUILD FAILED after $(secs "$t0" "$(now)")s (log: $log-build.log)"); failed=1
  fi
  size_report "$preset"
done

for run in "${runs[@]}"; do
  [ $test -eq 1 ] || break
  read -r preset cpu regex <<<"$run"
  [ -f "build/$preset/CTestTestfile.cmake" ] || {
    summary+=("$preset: NOT BUILT (run cross_test.sh ${which} --build-only first)"); failed=1; continue; }
  log=build/logs/cross-$preset-$cpu
  what="tests"; filter=()
  if [ -n "${regex:-}" ]; then what="the tests of its -R list"; filter=(-R "$regex"); fi
  echo "=== $preset: $what under qemu-aarch64 -cpu $cpu (-j$jobs)"
  t0=$(now)
  # TLVLINK_TEST_CPU: the tree's emulator runs qemu under this CPU (cmake/toolchains/qemu-aarch64-run.sh).
  TLVLINK_TEST_CPU=$cpu ctest --preset "$preset" -j "$jobs" --output-on-failure "${filter[@]}" >"$log-test.log" 2>&1
  rc=$?
  t_test=$(secs "$t0" "$(now)")
  # Everything but the per-test "Start"/"Passed" lines and ctest's search list for an unbuilt
  # test: failures with their output, the totals.
  grep -vE '^ *Start +[0-9]+:|Test +#[0-9]+: .* +Passed +' "$log-test.log" |
    awk '/^Looked in the following places:/ {skip = 1; next} /^Unable to find executable/ {skip = 0}
         !skip' | sed '/^$/N;/^\n$/D'
  # "97% tests passed, 1 tests failed out of 33" -> "32 passed, 1 failed"
  counts=$(grep -Eo "[0-9]+ tests failed out of [0-9]+" "$log-test.log" | tail -1 |
           awk '{printf "%d passed, %d failed", $6 - $1, $1}')
  if [ $rc -eq 0 ]; then
    summary+=("$preset: $what ${t_test}s under -cpu $cpu: ${counts:-no summary}")
  else
    summary+=("$preset: TESTS FAILED under -cpu $cpu (${counts:-no summary}) in ${t_test}s (log: $log-test.log)")
    failed=1
  fi
done

echo
echo "cross_test summary (install_deps ${t_install}s, sysroot ${t_sysroot}s, -j$jobs):"
printf '  %s\n' "${summary[@]}"
if [ $failed -eq 0 ]; then echo "cross_test: PASS"; else echo "cross_test: FAIL"; fi
exit $failed
