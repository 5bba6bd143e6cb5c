# shellcheck shell=bash
# Sourced (not run) by press_sequence.sh and fit_press_head.sh: scenarios of single-finger presses
# (`tlvlink sim scenario --grasps 0`) and tlvlinkd's play of finger A with every encoded frame's
# embedding reported, as fast as the daemon takes the frames (`realtime = false`: a replay read at
# speed waits for the daemon, so every frame is processed and a play is deterministic).
#   press_tools BUILD                      sets $tlvlink and $tlvlinkd (exit 1 when missing)
#   press_dir OUT SPEC                     the scenario's folder; SPEC = sensor:seed:presses[:markers]
#   press_render OUT SPEC                  renders it (kept when OUT holds it with the same options)
#   press_play OUT SPEC MODEL PATH RUN     plays it with MODEL -> DIR/RUN.jsonl (kept when made
#                                          with the same MODEL file, by checksum); PATH: offline
#                                          (the exact processed frames) or live (the cameras' raw
#                                          output through the board's decoder)
# Seeds 401-408 are the press scenarios' (unlike any set's or live_vs_offline.sh's).

press_tools() {
  tlvlink=$1/tools/cli/tlvlink
  tlvlinkd=$1/firmware/tlvlinkd/tlvlinkd
  local b
  for b in "$tlvlink" "$tlvlinkd"; do
    [ -x "$b" ] || { echo "press scenarios: $b missing (cmake --build --preset host)" >&2; exit 1; }
  done
}

press_dir() {
  local sensor seed
  IFS=: read -r sensor seed _ _ <<<"$2"
  echo "$1/$sensor-$seed"
}

press_render() {
  local sensor seed presses markers dir args
  IFS=: read -r sensor seed presses markers <<<"$2"
  dir=$(press_dir "$1" "$2")
  args=(--sensor "$sensor" --seed "$seed" --grasps 0 --presses "$presses" --offline)
  [ "${markers:-}" = markers ] && args+=(--markers)
  if [ -f "$dir/truth.jsonl" ] && [ "$(cat "$dir/args" 2>/dev/null)" = "${args[*]}" ]; then return; fi
  echo "== render $2"
  "$tlvlink" sim scenario -o "$dir" "${args[@]}" --overwrite | tail -1
  echo "${args[*]}" >"$dir/args"
  rm -f "$dir"/*.jsonl.model
}

press_play() {
  local spec=$2 model=$3 path=$4 sensor dir run sum w=320 h=240
  IFS=: read -r sensor _ <<<"$spec"
  dir=$(press_dir "$1" "$spec")
  run=$dir/$5
  sum=$(sha256sum "$model" | cut -c1-64)
  [ "$sensor" = digit ] && { w=240; h=320; }
  [ -s "$run.jsonl" ] && [ "$(cat "$run.jsonl.model" 2>/dev/null)" = "$sum" ] && return
  {
    printf 'model = "%s"\noutput = ["jsonl:%s"]\nverify_model = false\nembedding = true\n' \
      "$model" "$run.jsonl.partial"
    printf '[grasp]\nmode = "off"\n[[sensor]]\nname = "left"\nmodel = "%s"\nfinger = "A"\n' "$sensor"
    printf 'source = "replay"\nrealtime = false\n'
    if [ "$path" = live ]; then  # the sensor model's own camera format and view
      printf 'device = "%s"\n' "$dir/A.tlvraw"
    else
      printf 'device = "%s"\nformat = "rgb24"\nwidth = %d\nheight = %d\n' \
        "$dir/A.offline.tlvraw" "$w" "$h"
      printf 'crop = 0.0\njpeg_scale = 1\norientation = "upright"\n'
    fi
  } >"$run.toml"
  rm -f "$run.jsonl.partial"
  "$tlvlinkd" --config "$run.toml" 2>"$run.log" >/dev/null ||
    { tail -5 "$run.log"; echo "press scenarios: tlvlinkd failed ($run.log)" >&2; return 1; }
  mv "$run.jsonl.partial" "$run.jsonl"
  echo "$sum" >"$run.jsonl.model"
  echo "   $spec ($path, $(basename "$model")): $(grep -E '^ *drops:' "$run.log" | sed 's/^ *//')"
}

# Plays every SPEC with MODEL, $TLVLINK_PLAYS at a time (default 2: a play takes a core, the
# GelSight Mini's live path decoding its 8 MP MJPEG).
press_play_all() {  # OUT MODEL PATH RUN SPEC...
  local out=$1 model=$2 path=$3 run=$4 spec pids=() p failed=0
  shift 4
  for spec in "$@"; do
    press_play "$out" "$spec" "$model" "$path" "$run" &
    pids+=($!)
    if [ ${#pids[@]} -ge "${TLVLINK_PLAYS:-2}" ]; then
      for p in "${pids[@]}"; do wait "$p" || failed=1; done
      pids=()
    fi
  done
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
  return "$failed"
}
