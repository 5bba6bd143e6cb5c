# Helper functions for rig test scripts (sourced by /init before /rig/test.sh runs).
#
# Markers on the console, parsed by the host (tools/rig/riglib/markers.py):
#   RIG-INIT <uptime>   RIG-BEGIN <name>   RIG-PASS <name>   RIG-FAIL <name>: <reason>
#   RIG-SKIP <name>: <reason>   RIG-NOTE <name>: <text>   RIG-DONE <rc>
# A test's output goes to /tmp/rig-logs/<name>.log and is printed to the console only when it
# fails, between "RIG-LOG-BEGIN <name>" and "RIG-LOG-END <name>". Lines a test prints starting
# with "note: " (figures worth keeping) are forwarded as "RIG-NOTE <name>: <text>" in any case.

# Programs may call these functions too, through /bin/rig: `rig rig_vivid_unload`.

RIG_FAILED_FILE=/tmp/rig-failed
RIG_LOGS=/tmp/rig-logs

rig_begin() { echo "RIG-BEGIN $1"; }
rig_pass() { echo "RIG-PASS $1"; }
rig_fail() { echo "RIG-FAIL $1: $2"; echo "$1" >>"$RIG_FAILED_FILE"; }
rig_skip() { echo "RIG-SKIP $1: $2"; }
rig_notes() {  # NAME FILE
  sed -n 's/^note: \(.*\)/RIG-NOTE '"$1"': \1/p' "$2"
}
rig_dump() {  # NAME FILE: a failed test's log on the console
  echo "RIG-LOG-BEGIN $1"; tail -n 200 "$2"; echo "RIG-LOG-END $1"
}

# rig_run NAME SECONDS CMD [ARG...]: one test, bounded by SECONDS; CMD is a program or one of
# these functions (inside `sh -c '...'` call them as `rig FUNCTION`). Exit 0 passes, 77 skips (the reason is the last line of its output), anything else
# fails.
rig_run() {
  local name=$1 secs=$2 log rc
  shift 2
  log=$RIG_LOGS/$name.log
  rig_begin "$name"
  timeout "$secs" /bin/rig "$@" >"$log" 2>&1
  rc=$?
  rig_notes "$name" "$log"
  case $rc in
    0) rig_pass "$name" ;;
    77) rig_skip "$name" "$(tail -n 1 "$log")" ;;
    124|143) rig_fail "$name" "timed out after ${secs}s"; rig_dump "$name" "$log" ;;
    *) rig_fail "$name" "exit status $rc"; rig_dump "$name" "$log" ;;
  esac
  return 0
}

# rig_gtest BINARY [SECONDS] [FILTER]: every GoogleTest case of BINARY as its own rig test named
# <binary>.<Suite>.<Case>, each bounded by SECONDS (default 120). GTEST_SKIP becomes RIG-SKIP
# with the skip message as the reason.
rig_gtest() {
  local bin=$1 secs=${2:-120} filter=${3:-*} base suite line name log rc reason
  base=$(basename "$bin")
  if ! "$bin" --gtest_list_tests --gtest_filter="$filter" >"$RIG_LOGS/$base.list" 2>&1; then
    rig_begin "$base"; rig_fail "$base" "cannot list its tests"; rig_dump "$base" "$RIG_LOGS/$base.list"
    return 0
  fi
  while IFS= read -r line; do
    case "$line" in
      "  "*) ;;
      *) suite=${line%% *}; continue ;;
    esac
    line=${line#  }; line=${line%% *}
    name=$base.$suite$line
    log=$RIG_LOGS/$name.log
    rig_begin "$name"
    timeout "$secs" "$bin" --gtest_filter="$suite$line" --gtest_color=no >"$log" 2>&1
    rc=$?
    rig_notes "$name" "$log"
    if [ $rc -eq 0 ] && grep -q '^\[  SKIPPED \]' "$log"; then
      reason=$(awk '/: Skipped$/ {getline; print; exit}' "$log")
      rig_skip "$name" "${reason:-skipped}"
    elif [ $rc -eq 0 ]; then
      rig_pass "$name"
    elif [ $rc -eq 124 ] || [ $rc -eq 143 ]; then
      rig_fail "$name" "timed out after ${secs}s"; rig_dump "$name" "$log"
    else
      rig_fail "$name" "$(grep -m1 -E 'Failure|error' "$log" | cut -c1-160)"; rig_dump "$name" "$log"
    fi
  done <"$RIG_LOGS/$base.list"
  return 0
}

# rig_wait_for PATH SECONDS: wait (in 50 ms steps) until PATH exists.
rig_wait_for() {
  local n=$(( $2 * 20 ))
  while [ ! -e "$1" ] && [ $n -gt 0 ]; do sleep 0.05; n=$((n - 1)); done
  [ -e "$1" ]
}

# rig_wait_raw TTY SECONDS: wait (in 50 ms steps) until TTY opens and takes `stty raw -echo`.
# cdc-acm creates /dev/ttyACM<n> at probe, but opening it fails with EIO until the gadget has
# answered the line-state request: seen once in the self-test with the host's cores busy.
rig_wait_raw() {
  local n=$(( $2 * 20 ))
  until stty -F "$1" raw -echo 2>/dev/null; do
    [ $n -gt 0 ] || { stty -F "$1" raw -echo; return 1; }  # once more, to show the error
    sleep 0.05; n=$((n - 1))
  done
}

# The device node of a named virtio-serial port (the host names them with --port), e.g.
#   echo hello >"$(rig_port rig.data)"
rig_port() {
  local p
  for p in /sys/class/virtio-ports/*; do
    [ "$(cat "$p/name" 2>/dev/null)" = "$1" ] && { echo "/dev/${p##*/}"; return 0; }
  done
  return 1
}

# rig_send PORT [TEXT]: TEXT (or stdin) to the host through the named port.
rig_send() {
  local dev
  dev=$(rig_port "$1") || { echo "rig: no virtio port named $1" >&2; return 1; }
  if [ $# -gt 1 ]; then echo "$2" >"$dev"; else cat >"$dev"; fi
}

# The host directory given with --share, mounted at /mnt/host (virtio 9p).
rig_mount_share() {
  modprobe 9pnet_virtio && modprobe 9p && mkdir -p /mnt/host &&
    mount -t 9p -o trans=virtio,version=9p2000.L,msize=262144 host0 /mnt/host
}

# ---- V4L2: vivid, the kernel's virtual video test driver ----
# rig_vivid_load [PARAM...]: default "n_devs=1 node_types=0x101": one instance with a video
# capture node (inputs 0 webcam, 1 TV, 2 S-Video, 3 HDMI) and a video output node (outputs
# 0 S-Video, 1 HDMI). Output->capture loop: capture input 3 + output 1, the "Loop Video" control.
rig_vivid_load() {
  modprobe vivid ${*:-n_devs=1 node_types=0x101} || return 1
  rig_wait_for "$(rig_vivid_sysfs cap)" 5
}
rig_vivid_unload() { modprobe -r vivid; }
# rig_vivid_node cap|out: /dev/videoN of vivid instance 0's capture or output node.
rig_vivid_node() { local d; d=$(rig_vivid_sysfs "$1") && echo "/dev/${d##*/}"; }
rig_vivid_sysfs() {
  local d
  for d in /sys/class/video4linux/video*; do
    [ "$(cat "$d/name" 2>/dev/null)" = "vivid-000-vid-$1" ] && { echo "$d"; return 0; }
  done
  echo "/sys/class/video4linux/vivid-000-vid-$1-absent"; return 1
}

# ---- USB: dummy_hcd (host and device controllers in one kernel) and configfs gadgets ----
# rig_usb_load [N]: N UDC/host pairs (dummy_udc.0 ... N-1), default 1.
rig_usb_load() {
  modprobe dummy_hcd num="${1:-1}" && modprobe libcomposite && modprobe cdc-acm || return 1
  grep -q ' /sys/kernel/config ' /proc/mounts || mount -t configfs configfs /sys/kernel/config
  rig_wait_for /sys/class/udc/dummy_udc.0 5
}
# rig_gadget_acm NAME VID PID SERIAL UDC: a CDC-ACM gadget; the board side is /dev/ttyGS<n>, the
# host side (cdc-acm) /dev/ttyACM<n> once enumerated. rig_gadget_remove NAME undoes it.
rig_gadget_acm() {
  local g=/sys/kernel/config/usb_gadget/$1
  modprobe usb_f_acm || return 1
  mkdir -p "$g" "$g/strings/0x409" "$g/configs/c.1" "$g/functions/acm.0" || return 1
  echo "$2" >"$g/idVendor"; echo "$3" >"$g/idProduct"
  echo "$4" >"$g/strings/0x409/serialnumber"
  echo tlvlink >"$g/strings/0x409/manufacturer"; echo "rig $1" >"$g/strings/0x409/product"
  ln -s "$g/functions/acm.0" "$g/configs/c.1/"
  echo "$5" >"$g/UDC"
}
rig_gadget_unbind() { echo "" >"/sys/kernel/config/usb_gadget/$1/UDC"; }
rig_gadget_bind() { echo "$2" >"/sys/kernel/config/usb_gadget/$1/UDC"; }
rig_gadget_remove() {
  local g=/sys/kernel/config/usb_gadget/$1 f
  [ -d "$g" ] || return 0
  echo "" >"$g/UDC" 2>/dev/null
  for f in "$g"/configs/c.1/*.*; do [ -L "$f" ] && rm "$f"; done
  rmdir "$g/configs/c.1" "$g"/functions/* "$g/strings/0x409" "$g"
}
