#!/bin/sh
# The prediction stream over USB inside the emulated board (tools/rig): both ends run in the guest,
# joined by dummy_hcd — the board side on its UDC (FunctionFS bulk through our transport, or
# CDC-ACM /dev/ttyGS0), the host side on its root hub (libusb, or cdc-acm /dev/ttyACM0). The
# board is `tlvlink_stream_check board` (the real Sender posting fixture predictions: sensor n % 2,
# 120 Hz = two sensors at 60 fps, Stats every second), the host `tlvlink_stream_check check` (the
# real C++ client checking every field of every prediction). One scenario per call:
#   stream_usb.sh setup                    dummy_hcd with 2 UDCs; gadgets 'tlvlink' (FunctionFS,
#                                          dummy_udc.0) and 'tlvacm' (CDC-ACM, dummy_udc.1), both
#                                          1d6b:0104 with their own serial numbers
#   stream_usb.sh stream ffs|acm           a clean stream: every prediction intact, in order, no
#                                          rejected frame, every command answered
#   stream_usb.sh replug ffs|acm           gadget unbound (unplug) and bound again mid-stream
#   stream_usb.sh restart ffs|acm          host reader killed (SIGKILL) mid-stream, a new one started
#   stream_usb.sh corrupt ffs|acm ERR DROP bytes damaged between the Sender and the link (120 Hz)
#   stream_usb.sh bench ffs|acm            throughput: the board posts as fast as it can
# Exit 0 when the check passed. Figures are printed as "note:" lines (the rig keeps them).
# Runs under busybox sh; programs are found on PATH (/bin in the rig), usb_gadget.sh next to this file.
set -u
here=$(dirname "$0")
gadget_sh="$here/usb_gadget.sh"
ffs_link="usb:/dev/ffs-tlvlink,udc=dummy_udc.0,gadget=/sys/kernel/config/usb_gadget/tlvlink"
ffs_source="usb:1d6b:0104,serial=RIG-FFS-0001"
log=/tmp/stream-usb
mkdir -p "$log"

die() { echo "stream_usb: $*"; exit 1; }

board_link() { [ "$1" = ffs ] && echo "$ffs_link" || echo serial:/dev/ttyGS0; }
host_source() { [ "$1" = ffs ] && echo "$ffs_source" || echo serial:/dev/ttyACM0; }

# The FunctionFS gadget is bound by the board program itself (udc= in its link) once it has
# written its descriptors, and unbound by the kernel when it closes ep0; wait for that so the
# next scenario starts from an unbound gadget.
wait_ffs_released() {
  i=0
  while [ -n "$(cat /sys/kernel/config/usb_gadget/tlvlink/UDC 2>/dev/null)" ] && [ $i -lt 50 ]; do
    sleep 0.1; i=$((i + 1))
  done
}

# The host's USB device of the gadget (by its serial number), as its hub driver enumerated it.
host_sees() {  # ffs|acm
  serial=RIG-FFS-0001
  [ "$1" = acm ] && serial=RIG-ACM-0001
  cat /sys/bus/usb/devices/*/serial 2>/dev/null | grep -qx "$serial"
}

unplug() {  # ffs|acm
  if [ "$1" = ffs ]; then sh "$gadget_sh" unbind --name tlvlink
  else sh "$gadget_sh" unbind --name tlvacm --no-ffs; fi
}
plug() {
  if [ "$1" = ffs ]; then sh "$gadget_sh" bind --name tlvlink --udc dummy_udc.0
  else sh "$gadget_sh" bind --name tlvacm --no-ffs --udc dummy_udc.1; fi
}

# run_board KIND NAME ARGS...: the board in the background; its PID in $board_pid.
run_board() {
  kind=$1 name=$2
  shift 2
  tlvlink_stream_check board --link "$(board_link "$kind")" "$@" >"$log/$name.board" 2>&1 &
  board_pid=$!
}
# finish NAME CHECK_RC: waits for the board, prints both logs; fails if either failed.
finish() {
  wait "$board_pid"
  brc=$?
  echo "--- board"; cat "$log/$1.board"
  echo "--- host"; cat "$log/$1.check"
  [ "$2" -eq 0 ] || die "$1: the host side's check failed (exit $2)"
  [ "$brc" -eq 0 ] || die "$1: the board program failed (exit $brc)"
}

setup() {
  rig rig_usb_load 2 || die "dummy_hcd / libcomposite / cdc-acm did not load"
  sh "$gadget_sh" setup --name tlvlink --serial RIG-FFS-0001 || die "FunctionFS gadget set-up failed"
  sh "$gadget_sh" setup --name tlvacm --no-ffs --acm --serial RIG-ACM-0001 || die "CDC-ACM gadget set-up failed"
  sh "$gadget_sh" bind --name tlvacm --no-ffs --udc dummy_udc.1 || die "binding the CDC-ACM gadget failed"
  rig rig_wait_for /dev/ttyACM0 10 || die "/dev/ttyACM0 did not appear within 10 s of binding"
  [ -e /dev/ttyGS0 ] || die "no /dev/ttyGS0"
  ls /dev/ffs-tlvlink
}

stream() {  # KIND: 1,200 predictions at 120 Hz (two sensors at 60 fps), a clean link
  name=stream-$1
  [ "$1" = ffs ] && wait_ffs_released
  # The reader first: a CDC-ACM tty opened after the board started writing receives some bytes
  # before it is raw (they are dropped: the restart scenario covers a late reader).
  tlvlink_stream_check check --source "$(host_source "$1")" --frames 1200 --clean --timeout 90 \
    --label "usb-$1 stream (2 sensors x 60 fps)" >"$log/$name.check" 2>&1 &
  check_pid=$!
  sleep 0.5
  run_board "$1" "$name" --frames 1200 --rate 120 --hold 2
  wait "$check_pid"
  finish "$name" $?
}

replug() {  # KIND: unbind the gadget 4 s in for 1.5 s (at least), bind it again
  name=replug-$1
  [ "$1" = ffs ] && wait_ffs_released
  run_board "$1" "$name" --frames 1800 --rate 120 --hold 3
  tlvlink_stream_check check --source "$(host_source "$1")" --frames 1800 --lossy --expect-reconnects 1 \
    --expect-board-reconnects 1 --timeout 90 --label "usb-$1 replug" >"$log/$name.check" 2>&1 &
  check_pid=$!
  sleep 4
  echo "unplug (gadget unbound) at $(cut -d' ' -f1 /proc/uptime)"
  unplug "$1" || die "unbinding failed"
  # The host sees the unplug when its hub driver handles the port change; under emulation that
  # can come later than the 1.5 s, and a port found connected again is kept as it was: neither
  # end then sees an unplug (a flake of this check under TCG). So the gadget stays unbound until
  # the host's device is gone.
  i=0
  while host_sees "$1" && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
  host_sees "$1" && die "the host still lists the device 10 s after the gadget was unbound"
  echo "host device gone after $i x 0.1 s"
  sleep 1.5
  echo "replug (gadget bound) at $(cut -d' ' -f1 /proc/uptime)"
  plug "$1" || die "binding again failed"
  wait "$check_pid"
  finish "$name" $?
}

restart() {  # KIND: the host reader killed 4 s in; a new reader from wherever the stream is
  name=restart-$1
  [ "$1" = ffs ] && wait_ffs_released
  run_board "$1" "$name" --frames 1800 --rate 120 --hold 3
  timeout -s KILL 4 tlvlink_stream_check check --source "$(host_source "$1")" --frames 1800 --lossy \
    --timeout 90 --label "usb-$1 reader before the kill" >"$log/$name.first" 2>&1
  rc=$?
  [ $rc -eq 137 ] || die "the first reader was not killed (exit $rc): $(tail -n 3 "$log/$name.first")"
  grep -q "^check: connected" "$log/$name.first" || die "the first reader never connected"
  echo "first reader killed after 4 s (it had connected)"
  tlvlink_stream_check check --source "$(host_source "$1")" --frames 1800 --lossy --start-any --timeout 90 \
    --label "usb-$1 reader restarted" >"$log/$name.check" 2>&1
  finish "$name" $?
}

corrupt() {  # KIND ERR DROP: 1,200 predictions at 120 Hz with byte errors/drops at the stated rates
  name=corrupt-$1-$2-$3
  [ "$1" = ffs ] && wait_ffs_released
  run_board "$1" "$name" --frames 1200 --rate 120 --hold 2 --byte-errors "$2" --byte-drops "$3" --seed 1
  tlvlink_stream_check check --source "$(host_source "$1")" --frames 1200 --lossy --no-commands --idle 3 \
    --timeout 90 --label "usb-$1 corrupt $2 $3" >"$log/$name.check" 2>&1
  rc=$?
  wait "$board_pid"
  summary=$(grep '^check-summary' "$log/$name.check")
  damage=$(grep '^board-damage' "$log/$name.board")
  echo "--- board"; cat "$log/$name.board"
  echo "--- host"; cat "$log/$name.check"
  [ -n "$summary" ] && [ -n "$damage" ] || die "$name: no summary from the board or the host"
  echo "note: corruption $1 errors=$2 drops=$3 ${damage#board-damage } ${summary#check-summary }"
  [ $rc -eq 0 ] || die "$name: the host side's check failed (a corrupted prediction accepted, or none at all)"
}

bench() {  # KIND: 20,000 predictions posted as fast as the poster can; what the link delivers
  name=bench-$1
  [ "$1" = ffs ] && wait_ffs_released
  run_board "$1" "$name" --frames 20000 --rate 0 --hold 2
  tlvlink_stream_check check --source "$(host_source "$1")" --frames 20000 --lossy --no-commands --idle 3 \
    --timeout 120 --label "usb-$1 throughput (board posts as fast as it can)" >"$log/$name.check" 2>&1
  finish "$name" $?
}

case "${1:-}" in
  setup) setup ;;
  stream|replug|restart|bench) [ $# -eq 2 ] || die "usage: $0 $1 ffs|acm"; "$1" "$2" ;;
  corrupt) [ $# -eq 4 ] || die "usage: $0 corrupt ffs|acm ERR DROP"; corrupt "$2" "$3" "$4" ;;
  *) die "usage: $0 setup | stream|replug|restart|bench ffs|acm | corrupt ffs|acm ERR DROP" ;;
esac
