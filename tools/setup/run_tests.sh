#!/usr/bin/env bash
# The README's test command: sets up a fresh Debian 12 machine and runs every test stage.
#   tools/setup/run_tests.sh [stage ...]     stages: host minimal cross board asan fuzz   (default: all)
# Each stage builds into build/<preset> and runs its tests (logs in build/logs/); minimal builds the
# README's board-only configurations into build/minimal-* (see run_minimal); board runs the
# capture tests inside the emulated arm64 board (tools/setup/board_test.sh: QEMU virt + vivid).
# The closing line "tests: N passed, N failed" adds up every ctest run and every rig run (a
# failed build or fuzz stage counts as a failure). Set TLVLINK_FUZZ_SECONDS to change the
# fuzzing budget (shared between the fuzz targets).
set -uo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
stages=("$@")
# asan and fuzz last: their trees compile from the start, niced (start_later_builds); board runs
# beside the others once the trees it needs are built (start_board_beside).
[ ${#stages[@]} -eq 0 ] && stages=(host minimal cross board asan fuzz)
jobs=${TLVLINK_JOBS:-$(nproc)}
fuzz_seconds=${TLVLINK_FUZZ_SECONDS:-60}

bash tools/setup/install_deps.sh all || { echo "run_tests: dependency installation failed" >&2; exit 1; }

passed=0; failed=0; failed_names=(); stage_times=()
stage_start() { echo; echo "=== stage $1 ($(date -u +%H:%M:%S)) ==="; stage_t0=$(date +%s); }
stage_end() {  # $1 name, $2 status [, $3 seconds (default: since stage_start), $4 note]
  local dt=${3:-$(( $(date +%s) - stage_t0 ))} note=${4:+ ($4)}
  stage_times+=("$1 ${dt}s$note")
  if [ "$2" -eq 0 ]; then passed=$((passed + 1)); echo "=== stage $1 passed in ${dt}s$note ===";
  else failed=$((failed + 1)); failed_names+=("$1"); echo "=== stage $1 FAILED in ${dt}s$note ==="; fi
}

# Every tree this command configures keeps line tables only (-g1, TLVLINK_DEBUG_LINES in
# cmake/options.cmake): ~25 % less compile time, and failures still show file:line.
ci_cmake_args=(-DTLVLINK_DEBUG_LINES=ON)
# The large trees (host, host-asan, the two aarch64 trees) also compile as unity builds
# (TLVLINK_UNITY_BUILD: 8 sources per translation unit, the shared headers parsed once per batch):
# about a third of the compile time (tools/setup/README.md). The minimal and fuzz trees compile
# every file on its own, so a file that builds only beside its batch neighbours still fails here.
ci_tree_args=("${ci_cmake_args[@]}" -DTLVLINK_UNITY_BUILD=ON)
build_preset() {  # $1 preset
  cmake --preset "$1" "${ci_tree_args[@]}" >/dev/null && cmake --build --preset "$1" -j "$jobs"
}
build_and_test() {  # $1 preset
  build_preset "$1" && ctest --preset "$1" -j "$jobs" --output-on-failure
}

build_fuzz() {
  CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${ci_cmake_args[@]}" \
    -DTLVLINK_BUILD_FUZZERS=ON -DTLVLINK_BUILD_TESTS=OFF -DTLVLINK_WERROR=ON >/dev/null &&
    cmake --build build/fuzz -j "$jobs" --target model_loader_fuzz make_fuzz_corpus \
      stream_decoder_fuzz make_stream_fuzz_corpus file_parsers_fuzz make_parser_fuzz_corpus
}

# The board stage mostly waits on the emulated board's clock (its USB and capture scenarios run
# at camera rates: measured ~25 % of the 2 cores), and the stages before it leave the cores idle
# now and then (ctest's tails, configure and link steps). So the trees of the last two stages
# (asan, fuzz) compile from the start at the lowest priority, in whatever CPU the others leave;
# those stages then find their trees built and run their tests at full speed. A failed
# background build is simply built again, visibly, by its own stage.
later_builds_pid=
start_later_builds() {  # the stages of this run
  local s todo=()
  for s in "$@"; do case "$s" in asan|fuzz) todo+=("$s") ;; esac; done
  [ ${#todo[@]} -gt 0 ] || return 0
  echo "run_tests: building ${todo[*]} in the background (niced) while the other stages run"
  rm -f build/logs/later-build-*.done
  # One tree after the other (asan first); each leaves a marker when done, so the asan stage
  # starts as soon as its own tree is built while the fuzz tree goes on compiling beside it.
  ( renice -n 19 -p "$BASHPID" >/dev/null
    for s in "${todo[@]}"; do
      case "$s" in asan) build_preset host-asan ;; fuzz) build_fuzz ;; esac
      echo "later build $s: exit $? at $(date -u +%H:%M:%S)"
      touch "build/logs/later-build-$s.done"
    done ) >build/logs/later-builds.log 2>&1 &
  later_builds_pid=$!
}
wait_later_build() {  # $1 asan|fuzz: until that tree's background build has ended
  [ -n "$later_builds_pid" ] || return 0
  while [ ! -e "build/logs/later-build-$1.done" ] && kill -0 "$later_builds_pid" 2>/dev/null; do
    sleep 2
  done
  grep -E "^later build $1:" build/logs/later-builds.log
}

run_fuzz() {
  local dir=build/fuzz
  build_fuzz || return 1
  rm -rf "$dir/corpus" "$dir/stream_corpus" "$dir/parser_corpus" &&
    mkdir -p "$dir/corpus" "$dir/stream_corpus" "$dir/parser_corpus" "$dir/artifacts"
  "$dir/tests/fuzz/make_fuzz_corpus" "$dir/corpus" || return 1
  "$dir/tests/fuzz/make_stream_fuzz_corpus" "$dir/stream_corpus" || return 1
  "$dir/tests/fuzz/make_parser_fuzz_corpus" "$dir/parser_corpus" >/dev/null || return 1
  # The budget is split: half for the model loader, a quarter each for the stream decoder and
  # the file parsers (npy, PNM, PNG, JPEG, dataset indexes, recordings, camera frames).
  local loader_seconds=$(( fuzz_seconds / 2 ))
  local stream_seconds=$(( fuzz_seconds / 4 ))
  local parser_seconds=$(( fuzz_seconds - loader_seconds - stream_seconds ))
  # -max_len covers the largest seed (the 96-px fp32 reference encoder, ~670 KiB): libFuzzer
  # truncates longer seeds into invalid files. Executions stay in the millisecond range: the
  # fuzzer invokes only small models (its kMaxInvoke* caps), never the encoders.
  # Memory limits = the documented budgets (tools/cli/README.md "Memory budgets"): a model load
  # holds two copies of the file (2 x kMaxModelBytes = 512 MiB, the largest single allocation);
  # RSS adds libFuzzer's own (corpus, coverage maps). A bigger allocation is a finding.
  # Each fuzzer is one process on one core: the loader's half of the budget runs beside the
  # other two (one after the other), so the stage takes half its budget on two cores.
  "$dir/tests/fuzz/model_loader_fuzz" -max_total_time="$loader_seconds" -max_len=1048576 -timeout=10 \
    -rss_limit_mb=1024 -malloc_limit_mb=512 -artifact_prefix="$dir/artifacts/" -print_final_stats=1 \
    "$dir/corpus" 2>"$dir/fuzz.log" &
  local loader_pid=$!
  # The stream decoder allocates nothing per frame: tight limits make a runaway allocation a
  # finding. -max_len covers two largest wire frames.
  "$dir/tests/fuzz/stream_decoder_fuzz" -max_total_time="$stream_seconds" -max_len=33000 -timeout=10 \
    -rss_limit_mb=512 -malloc_limit_mb=64 -artifact_prefix="$dir/artifacts/stream-" -print_final_stats=1 \
    "$dir/stream_corpus" 2>"$dir/stream_fuzz.log"
  local stream_rc=$?
  echo "stream_decoder_fuzz (${stream_seconds}s):"
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb|Done [0-9]+ runs|cov: .* ft:|ERROR|SUMMARY" \
    "$dir/stream_fuzz.log" | tail -6
  [ $stream_rc -eq 0 ] || { tail -60 "$dir/stream_fuzz.log"; ls "$dir/artifacts"; }
  # -max_len covers the largest seed (a 320x240 YUYV camera frame, 150 KiB). Memory limits =
  # the image decode budget (tools/cli/README.md): one image of at most kMaxImagePixels (48 MiB
  # RGB, the largest single allocation, under 64 MiB) plus the decoder's working memory; RSS
  # adds libFuzzer's own. A decompression bomb (a header declaring more than its bytes can
  # hold) is a finding: before issue 12 this target peaked at ~572 MB.
  "$dir/tests/fuzz/file_parsers_fuzz" -max_total_time="$parser_seconds" -max_len=200000 -timeout=10 \
    -rss_limit_mb=384 -malloc_limit_mb=64 -artifact_prefix="$dir/artifacts/parser-" \
    -print_final_stats=1 "$dir/parser_corpus" 2>"$dir/parser_fuzz.log"
  local parser_rc=$?
  echo "file_parsers_fuzz (${parser_seconds}s):"
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb|Done [0-9]+ runs|cov: .* ft:|ERROR|SUMMARY" \
    "$dir/parser_fuzz.log" | tail -6
  [ $parser_rc -eq 0 ] || { tail -60 "$dir/parser_fuzz.log"; ls "$dir/artifacts"; }
  wait "$loader_pid"
  local rc=$?
  echo "model_loader_fuzz (${loader_seconds}s):"
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb|Done [0-9]+ runs|ERROR|SUMMARY" "$dir/fuzz.log" | head -20
  [ $rc -eq 0 ] || { tail -60 "$dir/fuzz.log"; ls "$dir/artifacts"; }
  [ $rc -eq 0 ] && [ $stream_rc -eq 0 ] && [ $parser_rc -eq 0 ]
}

# The README's minimal board builds, each configured on its own (no host-tool dependency may be
# needed): the runtime as a board program links it (tests/minimal; with XNNPACK it may use only
# XNNPACK, pthreadpool, cpuinfo and flatbuffers, without it only flatbuffers). The tree without
# XNNPACK also builds and runs the suites that need no host tools (model, reference executor,
# heads, verify, core: TLVLINK_MINIMAL_SUITES), which had a third tree of their own.
run_minimal() {
  local v name xnn t rc=0
  for v in board:ON:OFF reference:OFF:ON; do
    IFS=: read -r name xnn suites <<<"$v"
    t=$(date +%s)
    { cmake -S tests/minimal -B "build/minimal-$name" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${ci_cmake_args[@]}" \
        -DTLVLINK_WITH_XNNPACK="$xnn" -DTLVLINK_WITH_IMAGE="$xnn" -DTLVLINK_WITH_CAPTURE="$xnn" -DTLVLINK_WITH_PIPELINE="$xnn" -DTLVLINK_BUILD_DAEMON="$xnn" \
        -DTLVLINK_MINIMAL_SUITES="$suites" >/dev/null &&
        cmake --build "build/minimal-$name" -j "$jobs" &&
        ctest --test-dir "build/minimal-$name" -j "$jobs" --output-on-failure --no-tests=error; } || rc=1
    echo "minimal: $name runtime (XNNPACK $xnn, suites $suites) $(( $(date +%s) - t ))s"
  done
  return $rc
}

# The emulated board's stage: the rig's tests, then every board's package (tools/boards/ci_boards.sh).
# The two board trees no other stage builds compile beside the rig's tests (niced), which mostly
# wait.
run_board() {
  bash tools/boards/ci_boards.sh --prebuild >build/logs/boards-prebuild.log 2>&1 & local pre=$!
  bash tools/setup/board_test.sh all; local b=$?
  wait $pre; cat build/logs/boards-prebuild.log
  bash tools/boards/ci_boards.sh || b=1
  return $b
}

# The board stage runs beside the others instead of after them: it mostly waits on the emulated
# board's clock (camera rates, USB streams: ~25 % of the 2 cores over ~8 min), so queued it was a
# third of the run. It needs the host tree (its CLI and the HIL's reference) and the aarch64 trees
# (cross_test.sh --build-only) built first; nothing else writes them while it runs. The stages in
# the foreground then run at nice 5: the board's guest, whose tests keep camera time, goes first.
board_pid=
start_board_beside() {
  echo "run_tests: building the host and aarch64 trees, then the board stage beside the others"
  local t=$(date +%s)
  build_preset host >build/logs/host-build.log 2>&1 || { tail -30 build/logs/host-build.log; return 1; }
  TLVLINK_CROSS_CMAKE_ARGS="${TLVLINK_CROSS_CMAKE_ARGS:-} ${ci_tree_args[*]}" \
    bash tools/setup/cross_test.sh all --build-only >build/logs/cross-build.log 2>&1 ||
    { tail -30 build/logs/cross-build.log; return 1; }
  echo "run_tests: trees built in $(( $(date +%s) - t ))s"
  ( t=$(date +%s); run_board >build/logs/board.log 2>&1; echo "$? $(( $(date +%s) - t ))" >build/logs/board.status ) &
  board_pid=$!
  renice -n 5 -p $$ >/dev/null  # this shell and the foreground stages it starts from now on
}

run_stage() {  # $1 stage
  case "$1" in
    host) build_and_test host ;;
    minimal) run_minimal ;;
    asan) build_and_test host-asan ;;
    fuzz) run_fuzz ;;
    # Built already when the board stage runs beside (its trees): then only the tests.
    cross) local mode=(); [ -z "$board_pid" ] || mode=(--test-only)
           TLVLINK_CROSS_CMAKE_ARGS="${TLVLINK_CROSS_CMAKE_ARGS:-} ${ci_tree_args[*]}" \
             bash tools/setup/cross_test.sh all "${mode[@]}" ;;
    board) run_board ;;
    *) echo "run_tests: unknown stage '$1' (host minimal cross board asan fuzz)" >&2; return 2 ;;
  esac
}

t0=$(date +%s)
mkdir -p build/logs
# Compiled objects are reused across runs and clones (cmake/ccache.cmake): count this run's hits.
command -v ccache >/dev/null && ccache -z >/dev/null 2>&1
tests_passed=0; tests_failed=0
start_later_builds "${stages[@]}"
rm -f build/logs/board.status
if [[ " ${stages[*]} " == *" board "* ]] && [ ${#stages[@]} -gt 1 ]; then
  start_board_beside || echo "run_tests: the trees did not build: the board stage runs in its turn"
fi
# The foreground stages in their order; a board stage started beside them is reported last.
foreground=()
for s in "${stages[@]}"; do [ "$s" = board ] && [ -n "$board_pid" ] || foreground+=("$s"); done
[ -z "$board_pid" ] || foreground+=(board-beside)
for i in "${!foreground[@]}"; do
  s=${foreground[$i]}
  case "$s" in asan|fuzz) wait_later_build "$s" ;; esac
  if [ "$s" = board-beside ]; then  # wait for it, then count it like the others
    echo; echo "run_tests: waiting for the board stage ($(date -u +%H:%M:%S))"
    wait "$board_pid"
    read -r rc board_secs <build/logs/board.status 2>/dev/null || { rc=1 board_secs=0; }
    s=board log=build/logs/board.log
    cat "$log"
    stage_end board "$rc" "$board_secs" "beside the others"
  else
    stage_start "$s"
    log="build/logs/$s.log"
    run_stage "$s" 2>&1 | tee "$log"; rc=${PIPESTATUS[0]}
    stage_end "$s" "$rc"
  fi
  # ctest: "100% tests passed, 0 tests failed out of 57"
  counts=$(grep -Eo "tests passed, [0-9]+ tests failed out of [0-9]+" "$log" 2>/dev/null |
           awk '{f+=$3; t+=$8} END {print t-f, f+0}')
  # The board rig: "rig: tests 63 passed, 0 failed, 2 skipped; ..." (skipped are not counted as passed).
  rig_counts=$(grep -Eo "^rig: tests [0-9]+ passed, [0-9]+ failed" "$log" 2>/dev/null |
               awk '{p+=$3; f+=$5} END {print p+0, f+0}')
  read -r rp rf <<<"${rig_counts:-0 0}"
  read -r cp cf <<<"${counts:-0 0}"
  counts="$((cp + rp)) $((cf + rf))"
  read -r p f <<<"${counts:-0 0}"
  tests_passed=$((tests_passed + p)); tests_failed=$((tests_failed + f))
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then tests_failed=$((tests_failed + 1)); fi
done
[ -z "$later_builds_pid" ] || wait "$later_builds_pid"
# CI keeps only the end of this output: what failed is repeated here, a few lines per stage
# (the whole log stays in build/logs/<stage>.log).
for s in "${failed_names[@]}"; do
  echo
  echo "--- what failed in stage $s (build/logs/$s.log) ---"
  grep -E "\(Failed\)|\(Timeout\)|\(SEGFAULT\)|\(Subprocess aborted\)|(^|[^A-Za-z])FAIL(ED)?([^A-Za-z]|$)|MISMATCH|error:|Error [0-9]" \
    "build/logs/$s.log" 2>/dev/null | grep -vE "(^|[^0-9])0 (tests )?failed" | tail -25
  # The failed assertions themselves (GoogleTest's "file:line: Failure" and what follows), so that
  # a failure seen once in CI says what it was.
  grep -A4 -E ": Failure$" "build/logs/$s.log" 2>/dev/null | cut -c1-240 | head -20
done
echo
echo "run_tests: stage wall times: ${stage_times[*]}"
if command -v ccache >/dev/null; then
  echo "run_tests: ccache ($(ccache -k cache_dir 2>/dev/null)): $(ccache --print-stats 2>/dev/null |
    awk -F'\t' '$1=="direct_cache_hit"||$1=="preprocessed_cache_hit"{h+=$2} $1=="cache_miss"{m=$2} END {printf "%d hits, %d misses in this run", h, m}')"
fi
echo "run_tests: wall time $(( $(date +%s) - t0 ))s; failed stages: ${failed_names[*]:-none}"
echo "stages: $passed passed, $failed failed"
echo "tests: $tests_passed passed, $tests_failed failed"
[ "$failed" -eq 0 ]
