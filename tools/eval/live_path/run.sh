#!/usr/bin/env bash
# The live image path against the offline one, scene by scene (tools/eval/live_path/README.md).
#   tools/eval/live_path/run.sh BUILD OUT [MODEL]
# BUILD: a CMake build directory of this tree with the host tools (`tlvlink` and the two programs
# here, tools/eval/live_path/CMakeLists.txt); OUT: a work directory (~200 MB); MODEL: default firmware/models/touch-tiny-int8.tlvm;
# PYTHON: an interpreter with numpy (default python3).
# Builds live_path_frames and recording_frames in BUILD if needed, renders 200 touch-session presses
# (seed 77, half with markers) and 200 grasp "during" scenes (seed 2026, no markers, like
# `tlvlink sim scenario`) three ways and prints paths.py's table for each set.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../../.." && pwd)
build=$(cd "$1" && pwd)
out=$2
model=${3:-$src/firmware/models/touch-tiny-int8.tlvm}
tlvlink=$build/tools/cli/tlvlink
mkdir -p "$out"
for prog in live_path_frames recording_frames; do
  [ -x "$build/tools/eval/live_path/$prog" ] ||
    cmake --build "$build" --target "$prog" >/dev/null || { echo "run.sh: cannot build $prog" >&2; exit 1; }
done
for set in "touch 200 77 -1" "grasp 200 2026 0"; do
  read -r name n seed markers <<<"$set"
  mkdir -p "$out/$name"
  "$build/tools/eval/live_path/live_path_frames" "$name" "$n" "$seed" "$markers" "$out/$name"
  "${PYTHON:-python3}" "$here/paths.py" "$tlvlink" "$model" "$out/$name"
done
