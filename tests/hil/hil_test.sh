#!/usr/bin/env bash
# Hardware-in-the-loop run of tlvlinkd in the emulated board (tests/hil/README.md):
#   1. simulated GelSight frames: `tlvlink sim scenario --sensor digit-640x480` (finger A: YUYV
#      640x480, contact and no contact), cached in build/hil/share/frames;
#   2. the host reference: the host build's tlvlinkd replays the same recording (every record,
#      `embedding = true`, gating and smoothing off) into build/hil/host.jsonl;
#   3. per board preset, one boot (tools/rig): the cross-built tlvlinkd reads the frames from
#      vivid's capture node and streams over the FunctionFS gadget (CDC-ACM in the garbage run) to
#      the USB host side in the guest, JSON lines over virtio-serial (tests/hil/rig/);
#   4. tests/hil/host/hil_compare.py compares every prediction with the host's and counts, per
#      fault run, predictions computed vs delivered against the documented bounds.
#   hil_test.sh [a76|a72|all]   (a76: clean + fault runs on -cpu cortex-a76, generic-a76 build;
#                                a72: the clean run on -cpu cortex-a72, rpi4-a72 build; default all)
# Expects the cross builds of tlvlinkd, tlvlink_hil_feeder and tlvlink_hil_relay in
# build/<preset>/ (tools/setup/board_test.sh builds them) and builds the host's tlvlink and
# tlvlinkd if missing. Environment: PYTHON (default /usr/bin/python3), TLVLINK_JOBS (default 2).
# Exit 0 when every run passed; the guest's log is printed on failure (tools/rig).
set -uo pipefail
cd "$(dirname "$0")/../.."

which=${1:-all}
py=${PYTHON:-/usr/bin/python3}
jobs=${TLVLINK_JOBS:-2}
case "$which" in
  a76) runs=(generic-a76) ;;
  a72) runs=(rpi4-a72) ;;
  all) runs=(generic-a76 rpi4-a72) ;;
  *) echo "hil_test.sh: unknown target '$which' (a76|a72|all)" >&2; exit 2 ;;
esac
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.1f", b - a}'; }
dir=build/hil
cli=build/host/tools/cli/tlvlink
host_daemon=build/host/firmware/tlvlinkd/tlvlinkd
model=firmware/models/touch-tiny-int8.tlvm
mkdir -p "$dir" build/logs

t0=$(now)
frames=$dir/share/frames
if { [ ! -s "$frames/A.tlvraw" ] && [ ! -x "$cli" ]; } || [ ! -x "$host_daemon" ]; then
  { cmake --preset host && cmake --build --preset host -j "$jobs" --target tlvlink tlvlinkd; } \
    >build/logs/hil-host-build.log 2>&1 ||
    { tail -30 build/logs/hil-host-build.log; echo "hil: building the host's tlvlink / tlvlinkd failed" >&2; exit 1; }
fi

# 1. Frames (seeded: the same frames every run; re-rendered only when missing).
if [ ! -s "$frames/A.tlvraw" ]; then
  rm -rf "$frames" && mkdir -p "$dir/share"
  "$cli" sim scenario -o "$frames" --sensor digit-640x480 --grasps 3 --presses 2 --seed 15 \
    >build/logs/hil-frames.log 2>&1 || { cat build/logs/hil-frames.log; echo "hil: rendering the frames failed" >&2; exit 1; }
fi
echo "hil: frames $(tail -1 build/logs/hil-frames.log 2>/dev/null | sed 's/^scenario //') ($(secs "$t0" "$(now)")s)"

# 2. The host reference: every record of the recording, at the camera's pace (the replay's
#    newest-frame rule would skip frames if replayed faster than the host can process them).
t0=$(now)
rm -f "$dir/host.jsonl"
cat >"$dir/host.toml" <<EOF
model = "$PWD/$model"
executor = "xnnpack"
embedding = true
smoothing_ms = 0
output = "jsonl:$PWD/$dir/host.jsonl"
queue_frames = 16
output_queue = 4096
[contact]
enabled = false
[grasp]
mode = "off"
[[sensor]]
name = "A"
model = "digit-640x480"
source = "replay"
device = "$PWD/$frames/A.tlvraw"
EOF
rm -f "$dir/host.jsonl"
"$host_daemon" --config "$dir/host.toml" >build/logs/hil-host-reference.log 2>&1 ||
  { tail -20 build/logs/hil-host-reference.log; echo "hil: the host reference run failed" >&2; exit 1; }
echo "hil: host reference $(grep -c '"type":"frame_prediction"' "$dir/host.jsonl") predictions ($(secs "$t0" "$(now)")s)"

# 3 + 4. One boot per preset, then the comparison.
failed=0
for preset in "${runs[@]}"; do
  cpu=$(sed -n 's/.*"TLVLINK_QEMU_CPU": "\([^"]*\)".*/\1/p' "boards/$preset.json")
  faults=1
  [ "$preset" = rpi4-a72 ] && faults=0
  out=$dir/$preset
  rm -rf "$out" "$dir/share/out/$preset" && mkdir -p "$out" "$dir/share/out/$preset"
  args=()
  for p in firmware/tlvlinkd/tlvlinkd tests/hil/tlvlink_hil_feeder tests/hil/tlvlink_hil_relay; do
    [ -x "build/$preset/$p" ] || { echo "hil: build/$preset/$p is missing (cmake --build --preset $preset --target $(basename "$p"))" >&2; exit 1; }
    args+=(--program "build/$preset/$p")
  done
  echo "=== hil $preset: rig -cpu $cpu ($([ $faults = 1 ] && echo "clean + fault runs" || echo "clean run"))"
  t0=$(now)
  "$py" tools/rig/rig.py run --cpu "$cpu" --script tests/hil/rig/hil_rig.sh "${args[@]}" \
    --file tests/hil/rig/hil_guest.sh:/payload/hil/hil_guest.sh \
    --file runtime/transport/scripts/usb_gadget.sh:/payload/hil/usb_gadget.sh \
    --file "$model:/payload/hil/touch-tiny-int8.tlvm" \
    --share "$dir/share" --port hil.jsonl --env "HIL_FAULTS=$faults" --env "HIL_OUT=/mnt/host/out/$preset" \
    --env TLVLINK_RIG=1 --out "$out/rig" | tee "$out/rig.log"
  rc=${PIPESTATUS[0]}
  echo "hil $preset: rig exit $rc in $(secs "$t0" "$(now)")s"
  [ "$rc" -eq 0 ] || failed=1
  "$py" tests/hil/host/hil_compare.py --host "$dir/host.jsonl" --guest-jsonl "$out/rig/hil.jsonl.bin" \
    --relay "$dir/share/out/$preset" --rig-log "$out/rig.log" --label "$preset (-cpu $cpu)" |
    tee "$out/compare.log"
  [ "${PIPESTATUS[0]}" -eq 0 ] || failed=1
done
[ $failed -eq 0 ] && echo "hil: PASS" || echo "hil: FAIL"
exit $failed
