#!/usr/bin/env bash
# The live image path against the offline one, scene by scene (tools/eval/live_path/README.md).
#   tools/eval/live_path/run.sh BUILD OUT [MODEL]
# BUILD: a CMake build directory of this tree where `tlvlink` is built (its static libraries are
# linked); OUT: a work directory (~200 MB); MODEL: default firmware/models/touch-tiny-int8.tlvm;
# PYTHON: an interpreter with numpy (default python3).
# Compiles live_path_frames and recording_frames against BUILD, renders 200 touch-session presses
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
inc=()
for d in tools/sim/include runtime/include runtime/core/include runtime/model/include \
         runtime/executor/include runtime/heads/include runtime/image/include runtime/capture/include; do
  inc+=(-I"$src/$d")
done
lib() { echo "$build/$1"; }
c++ -std=c++20 -O2 "${inc[@]}" "$here/live_path_frames.cc" -o "$out/live_path_frames" \
  "$(lib tools/sim/src/gen/libtlvlink_sim_gen.a)" "$(lib tools/sim/src/gen/libtlvlink_sim_gen_core.a)" \
  "$(lib tools/sim/src/raw/libtlvlink_sim_raw.a)" "$(lib tools/sim/src/render/libtlvlink_sim_render.a)" \
  "$(lib runtime/image/libtlvlink_image.a)" "$(lib runtime/model/libtlvlink_model.a)" \
  "$(lib runtime/core/libtlvlink_core.a)" -lturbojpeg -ljpeg -lpthread
c++ -std=c++20 -O2 "${inc[@]}" "$here/recording_frames.cc" -o "$out/recording_frames" \
  "$(lib runtime/capture/libtlvlink_capture.a)" "$(lib runtime/image/libtlvlink_image.a)" \
  "$(lib runtime/model/libtlvlink_model.a)" "$(lib runtime/core/libtlvlink_core.a)" \
  -lturbojpeg -ljpeg -lpthread
for set in "touch 200 77 -1" "grasp 200 2026 0"; do
  read -r name n seed markers <<<"$set"
  mkdir -p "$out/$name"
  "$out/live_path_frames" "$name" "$n" "$seed" "$markers" "$out/$name"
  "${PYTHON:-python3}" "$here/paths.py" "$tlvlink" "$model" "$out/$name"
done
