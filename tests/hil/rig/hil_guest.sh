#!/bin/sh
# Hardware-in-the-loop scenarios inside the emulated board (tools/rig; tests/hil/README.md).
# Simulated GelSight frames go into vivid's output node (tlvlink_hil_feeder) and come out of its
# capture node, which tlvlinkd reads as its camera (through /tmp/hil-cam, a link that exists only
# while the loop is set up: the udev rule's stand-in); tlvlinkd runs the shipped int8 model with
# `embedding = true` and writes JSON lines to the virtio-serial port hil.jsonl (live, to the host)
# and the stream to the FunctionFS gadget (or CDC-ACM), whose USB host side — libusb through
# dummy_hcd, in this same guest — is tlvlink_hil_relay, recording every byte into
# \$HIL_OUT/SCENARIO/ (the host's directory, virtio 9p). The host compares it all afterwards.
#   hil_guest.sh setup                 dummy_hcd + gadgets 'tlvlink' (FunctionFS) and 'tlvacm'
#                                      (CDC-ACM, bound), vivid
#   hil_guest.sh clean                 every distinct frame of the recording, nothing disturbed
#   hil_guest.sh vivid_reload          vivid unplugged (platform unbind), unloaded, reloaded
#   hil_guest.sh reader_restart        the USB host reader SIGKILLed and started again
#   hil_guest.sh garbage               CDC-ACM link; random bytes injected both ways
#   hil_guest.sh replug                the gadget unbound and bound again
#   hil_guest.sh daemon_kill           tlvlinkd SIGKILLed, restarted by a supervisor loop
# Environment: HIL_RECORDING (the frames), HIL_MODEL, HIL_INTERVAL_MS (feed period, default 200),
# HIL_OUT (where the relay's recordings go, default /mnt/host/out).
# Each scenario writes {"type":"hil",...} marker lines into the JSON-lines port around its run
# and prints "note: ..." lines with what happened when (guest uptime). Exit 0 when every step
# ran; the verdict on the predictions is the host's (tests/hil/host/hil_compare.py).
set -u
here=$(dirname "$0")
gadget_sh="$here/usb_gadget.sh"
recording=${HIL_RECORDING:-/mnt/host/frames/A.tlvraw}
model=${HIL_MODEL:-/payload/hil/touch-tiny-int8.tlvm}
interval=${HIL_INTERVAL_MS:-200}
out=${HIL_OUT:-/mnt/host/out}
ffs_link="usb:/dev/ffs-tlvlink,udc=dummy_udc.0,gadget=/sys/kernel/config/usb_gadget/tlvlink"
ffs_source="usb:1d6b:0104,serial=HIL-FFS-0001"
cam=/tmp/hil-cam
work=/tmp/hil
mkdir -p "$work"

die() { echo "hil: $*"; exit 1; }
up() { cut -d' ' -f1 /proc/uptime; }
jsonl_port() { rig rig_port hil.jsonl; }
# Markers go to $out/SCENARIO/events.jsonl; begin, end and daemon_start (written while no daemon
# runs) also into the JSON-lines port, where they split the daemons' lines into runs. (A virtio
# console port takes one opener at a time: while tlvlinkd has it open, an echo into it fails.)
mark() {  # SCENARIO EVENT [EXTRA_JSON]
  line="{\"type\":\"hil\",\"scenario\":\"$1\",\"event\":\"$2\",\"uptime_s\":$(up)${3:+,$3}}"
  mkdir -p "$out/$1" && echo "$line" >>"$out/$1/events.jsonl"
  case "$2" in begin|end|daemon_start) echo "$line" >>"$port" || die "$1: marker '$2' could not be written to $port" ;; esac
}

# ---- the camera: feeder + the link the daemon opens ----
start_camera() {  # FIRST COUNT
  rm -f "$work/ready" "$cam"
  tlvlink_hil_feeder --recording "$recording" --first "$1" --count "$2" --interval-ms "$interval" \
    --hold-s 600 --ready "$work/ready" >>"$work/feeder.log" 2>&1 &
  feeder_pid=$!
  rig rig_wait_for "$work/ready" 20 || { cat "$work/feeder.log"; die "the feeder did not start the loop within 20 s"; }
  ln -s "$(rig rig_vivid_node cap)" "$cam"
}
stop_camera() { rm -f "$cam"; kill "$feeder_pid" 2>/dev/null; wait "$feeder_pid" 2>/dev/null; }
# Waits until the feeder has fed every frame (its "fed" line), at most SECONDS.
wait_fed() {
  n=$(( $1 * 10 ))
  while [ $n -gt 0 ] && [ "$(grep -c '^feeder: fed' "$work/feeder.log")" -lt "$2" ]; do sleep 0.1; n=$((n - 1)); done
  [ $n -gt 0 ] || { tail -5 "$work/feeder.log"; die "the feeder did not finish within $1 s"; }
}

# ---- the daemon ----
write_config() {  # LINK
  cat >"$work/tlvlinkd.toml" <<EOF
model = "$model"
executor = "xnnpack"
threads = 1
embedding = true           # the comparison needs the embedding and its int8 tensor
smoothing_ms = 0           # per-frame values: each prediction depends on its frame only
output = ["jsonl:$port", "$1"]
status_interval_ms = 500
queue_frames = 2
output_queue = 1024
[contact]
enabled = false            # every frame encoded (gating is stateful across frames)
[grasp]
mode = "off"
[[sensor]]
name = "A"
model = "digit-640x480"    # vivid's loop runs at 640x480 (its smallest HDMI timing)
source = "v4l2"
device = "$cam"
fps = 0                    # the HDMI loop's own rate
warmup_frames = 4          # vivid shows its own pattern for a frame or two after STREAMON
controls = "osd_text_mode=2, loop_video=1"
EOF
}
start_daemon() {  # LINK
  write_config "$1"
  tlvlinkd --config "$work/tlvlinkd.toml" >>"$work/daemon.log" 2>&1 &
  daemon_pid=$!
}
stop_daemon() {  # SIGTERM: frames already decoded are processed, records flushed, summary written
  kill -TERM "$daemon_pid" 2>/dev/null
  n=150
  while kill -0 "$daemon_pid" 2>/dev/null && [ $n -gt 0 ]; do sleep 0.1; n=$((n - 1)); done
  kill -0 "$daemon_pid" 2>/dev/null && { kill -KILL "$daemon_pid"; die "tlvlinkd did not stop within 15 s of SIGTERM"; }
  wait "$daemon_pid" 2>/dev/null
}

# ---- the USB host side ----
start_relay() {  # SCENARIO NAME SOURCE
  mkdir -p "$out/$1"
  tlvlink_hil_relay --source "$3" --record "$out/$1/$2.tlvrec" --timeout 300 --label "$2" \
    >>"$work/relay-$1.log" 2>&1 &
  relay_pid=$!
}
stop_relay() {  # after the daemon stopped: the last records have left the board
  sleep 2
  kill -TERM "$relay_pid" 2>/dev/null
  wait "$relay_pid" 2>/dev/null
}
wait_first_prediction() {  # SCENARIO SECONDS
  n=$(( $2 * 10 ))
  while [ $n -gt 0 ] && ! grep -q "first prediction" "$work/relay-$1.log" 2>/dev/null; do sleep 0.1; n=$((n - 1)); done
  [ $n -gt 0 ] || { tail -20 "$work/daemon.log"; die "$1: no prediction reached the USB host within $2 s"; }
}

# One scenario from a clean start: the camera and daemon up, a prediction through, ACTION, the
# rest of the frames, then everything stopped in order.
begin() {  # SCENARIO LINK SOURCE FIRST COUNT
  : >"$work/feeder.log"; : >"$work/daemon.log"
  mark "$1" begin
  start_camera "$4" "$5"
  start_relay "$1" reader "$3"
  start_daemon "$2"
}
finish() {  # SCENARIO FEEDS [SECONDS]
  wait_fed "${3:-120}" "$2"
  sleep 1.5  # the last fed frame is captured a few more times
  stop_daemon
  stop_relay
  stop_camera
  mark "$1" end
  cp "$work/daemon.log" "$work/feeder.log" "$work/relay-$1.log" "$out/$1/" 2>/dev/null
  echo "--- daemon"; cat "$work/daemon.log"
  echo "--- relay"; cat "$work/relay-$1.log"
  echo "--- feeder"; cat "$work/feeder.log"
  grep "^relay-summary" "$work/relay-$1.log" | sed 's/^/note: /'
  # The daemon's stream at stop (posted, sent, dropped, unsent): why a last prediction is missing.
  grep -E "stream: .*(posted|not sent)" "$work/daemon.log" | sed 's/^.*stream: /note: daemon stream: /'
}

setup() {
  port=$(jsonl_port) || die "no virtio-serial port named hil.jsonl (rig.py --port hil.jsonl)"
  [ -r "$recording" ] || die "no frames at $recording (the host's share: rig.py --share)"
  rig rig_usb_load 2 || die "dummy_hcd / libcomposite / cdc-acm did not load"
  sh "$gadget_sh" setup --name tlvlink --serial HIL-FFS-0001 || die "FunctionFS gadget set-up failed"
  sh "$gadget_sh" setup --name tlvacm --no-ffs --acm --serial HIL-ACM-0001 || die "CDC-ACM gadget set-up failed"
  sh "$gadget_sh" bind --name tlvacm --no-ffs --udc dummy_udc.1 || die "binding the CDC-ACM gadget failed"
  rig rig_wait_for /dev/ttyACM0 10 || die "/dev/ttyACM0 did not appear within 10 s of binding"
  rig rig_vivid_load || die "vivid did not load"
  echo "note: setup done at uptime $(up)"
}

clean() {
  begin clean "$ffs_link" "$ffs_source" 0 0
  wait_first_prediction clean 90
  echo "note: first prediction at the USB host at guest uptime $(grep -m1 'first prediction' "$work/relay-clean.log" | sed 's/.*uptime \([0-9.]*\).*/\1/') s"
  finish clean 1 240
}

vivid_reload() {  # frames 0..49, the camera unplugged and its module reloaded, frames 50..99
  begin vivid_reload "$ffs_link" "$ffs_source" 0 50
  wait_first_prediction vivid_reload 60
  sleep 4
  echo "note: vivid unbound (unplug) at $(up)"
  rm -f "$cam"
  echo vivid.0 >/sys/bus/platform/drivers/vivid/unbind || die "unbinding vivid.0 failed"
  kill "$feeder_pid" 2>/dev/null; wait "$feeder_pid" 2>/dev/null
  n=50
  until rig rig_vivid_unload 2>/dev/null; do
    n=$((n - 1)); [ $n -gt 0 ] || die "vivid could not be unloaded within 5 s (a node still open?)"; sleep 0.1
  done
  echo "note: vivid unloaded at $(up)"
  sleep 1
  rig rig_vivid_load || die "vivid did not load again"
  echo "note: vivid loaded again at $(up)"
  start_camera 50 50
  finish vivid_reload 1
}

reader_restart() {  # the USB host reader SIGKILLed 4 s after the first prediction, a new one 2 s later
  begin reader_restart "$ffs_link" "$ffs_source" 0 60
  wait_first_prediction reader_restart 60
  sleep 4
  kill -KILL "$relay_pid"; wait "$relay_pid" 2>/dev/null
  echo "note: reader killed at $(up)"
  mark reader_restart reader_killed
  sleep 2
  start_relay reader_restart reader2 "$ffs_source"
  echo "note: reader restarted at $(up)"
  finish reader_restart 1
}

garbage() {  # CDC-ACM: 3 bursts of 2 KiB random bytes into the stream (board side) and 3 into
             # the command direction (host side), 1 s apart
  begin garbage serial:/dev/ttyGS0 serial:/dev/ttyACM0 0 60
  wait_first_prediction garbage 60
  sleep 2
  mark garbage garbage_begin
  for i in 1 2 3; do
    head -c 2048 /dev/urandom >/dev/ttyGS0 || die "writing garbage into /dev/ttyGS0 failed"
    head -c 2048 /dev/urandom >/dev/ttyACM0 || die "writing garbage into /dev/ttyACM0 failed"
    echo "note: garbage burst $i (2 KiB each way) at $(up)"
    sleep 1
  done
  mark garbage garbage_end '"bursts":3'
  finish garbage 1
}

replug() {  # the FunctionFS gadget unbound 4 s after the first prediction, bound 2 s later
  begin replug "$ffs_link" "$ffs_source" 0 60
  wait_first_prediction replug 60
  sleep 4
  sh "$gadget_sh" unbind --name tlvlink || die "unbinding the gadget failed"
  echo "note: gadget unbound at $(up)"
  mark replug unplug
  sleep 2
  sh "$gadget_sh" bind --name tlvlink --udc dummy_udc.0 || die "binding the gadget again failed"
  echo "note: gadget bound again at $(up)"
  finish replug 1
}

# systemd's Restart=on-failure / RestartPreventExitStatus=2 / RestartSec=0.5 as a shell loop
# (firmware/tlvlinkd/tlvlinkd.service): each start is marked in the JSON lines.
supervise() {
  while :; do
    mark daemon_kill daemon_start
    tlvlinkd --config "$work/tlvlinkd.toml" >>"$work/daemon.log" 2>&1 &
    echo $! >"$work/daemon.pid"
    wait $!
    rc=$?
    echo "supervisor: tlvlinkd exited $rc at $(up)" >>"$work/daemon.log"
    [ $rc -eq 0 ] || [ $rc -eq 2 ] || [ -e "$work/stop" ] && break
    sleep 0.5
  done
}
daemon_kill() {  # tlvlinkd SIGKILLed 4 s after the first prediction; the supervisor restarts it
  : >"$work/feeder.log"; : >"$work/daemon.log"; rm -f "$work/stop"
  mark daemon_kill begin
  start_camera 0 70
  start_relay daemon_kill reader "$ffs_source"
  write_config "$ffs_link"
  supervise &
  supervisor_pid=$!
  wait_first_prediction daemon_kill 60
  sleep 4
  first=$(cat "$work/daemon.pid")
  kill -KILL "$first"
  echo "note: tlvlinkd (pid $first) SIGKILLed at $(up)"
  mark daemon_kill killed "\"pid\":$first"
  n=100
  while [ "$(cat "$work/daemon.pid")" = "$first" ] && [ $n -gt 0 ]; do sleep 0.1; n=$((n - 1)); done
  [ $n -gt 0 ] || die "the supervisor did not restart tlvlinkd within 10 s"
  echo "note: restarted as pid $(cat "$work/daemon.pid") at $(up)"
  daemon_pid=$(cat "$work/daemon.pid")
  touch "$work/stop"
  wait_fed 120 1
  sleep 1.5
  stop_daemon
  wait "$supervisor_pid" 2>/dev/null
  stop_relay
  stop_camera
  mark daemon_kill end
  cp "$work/daemon.log" "$work/feeder.log" "$work/relay-daemon_kill.log" "$out/daemon_kill/" 2>/dev/null
  echo "--- daemon"; cat "$work/daemon.log"
  echo "--- relay"; cat "$work/relay-daemon_kill.log"
  grep "^relay-summary" "$work/relay-daemon_kill.log" | sed 's/^/note: /'
}

port=$(jsonl_port) || die "no virtio-serial port named hil.jsonl"
case "${1:-}" in
  setup|clean|vivid_reload|reader_restart|garbage|replug|daemon_kill) "$1" ;;
  *) die "usage: $0 setup|clean|vivid_reload|reader_restart|garbage|replug|daemon_kill" ;;
esac
