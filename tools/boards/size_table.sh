#!/usr/bin/env bash
# Size table of the board packages (boards/README.md, between the size-table markers): for each
# board x scene built, the stripped tlvlinkd, the runtime's component libraries (text+data), the
# stripped model, the .deb, and what was left out. Uses `tlvlink flash` (build/host's CLI).
#   tools/boards/size_table.sh [--all] [--write]
# Default (CI): the scenes' distinct option sets on rpi5-a76 (usb / serial / JSON lines only)
# and every other ARM board with grasp-two-mini: 3 + 4 cross builds of tlvlinkd alone. --all:
# every board x scene. --write: replace the table in boards/README.md (else print it).
# Environment: TLVLINK_JOBS (default 2), TLVLINK_CLI (default build/host/tools/cli/tlvlink).
set -uo pipefail
cd "$(dirname "$0")/../.."
jobs=${TLVLINK_JOBS:-2}
cli=${TLVLINK_CLI:-build/host/tools/cli/tlvlink}
all=0 write=0
for a in "$@"; do
  case "$a" in --all) all=1 ;; --write) write=1 ;; *) echo "size_table.sh: unknown argument '$a'" >&2; exit 2 ;; esac
done
[ -x "$cli" ] || { echo "size_table.sh: $cli not built (cmake --build build/host --target tlvlink)" >&2; exit 1; }

scenes=(grasp-two-mini material-sort-mini surface-log-digit full-two-mini)
arm_boards=(rpi4-a72 rpi5-a76 jetson-orin-nano rk3588 qemu-virt-a76)
pairs=()
if [ $all -eq 1 ]; then
  for b in "${arm_boards[@]}"; do for s in "${scenes[@]}"; do pairs+=("$b $s"); done; done
else
  for s in grasp-two-mini material-sort-mini surface-log-digit; do pairs+=("rpi5-a76 $s"); done
  for b in rpi4-a72 jetson-orin-nano rk3588 qemu-virt-a76; do pairs+=("$b grasp-two-mini"); done
fi

kb() { awk -v b="$1" 'BEGIN {printf "%.0f KB", b / 1024}'; }
rows=() failed=0
for p in "${pairs[@]}"; do
  read -r board scene <<<"$p"
  out=build/flash/$board-$scene
  t0=$(date +%s)
  if ! log=$("$cli" flash --board "$board" --scene "$scene" -o build/flash -j "$jobs" 2>&1); then
    echo "$log" | tail -5 >&2
    rows+=("| $board | $scene | FAILED | | | | |"); failed=1; continue
  fi
  dt=$(( $(date +%s) - t0 ))
  daemon=$(stat -c %s "$out/root/usr/bin/tlvlinkd")
  libs=0
  for a in "$out"/build/runtime/*/libtlvlink_*.a "$out"/build/firmware/tlvlinkd/libtlvlink_daemon.a; do
    [ -f "$a" ] && libs=$(( libs + $(aarch64-linux-gnu-size -t "$a" | awk 'END {print $1 + $2}') ))
  done
  model=$(stat -c %s "$out/$scene.tlvm")
  deb=$(stat -c %s "$out"/tlvlink_*.deb)
  left=$(echo "$log" | awk '/^left out:/ {on = 1; next} /^kept without/ {on = 0} on' |
         sed 's/^ *//; s/ (.*//' | grep -v '^tests, host tools' | paste -sd ';' | sed 's/;/; /g')
  rows+=("| $board | $scene | $(kb "$daemon") | $(kb "$libs") | $(kb "$model") | $(kb "$deb") | ${left:-—} |")
  echo "size_table: $board x $scene in ${dt}s" >&2
done

table=$(printf '%s\n' "| board | scene | tlvlinkd (stripped) | runtime + daemon libraries (text+data) | model (stripped) | .deb | left out (besides tests, host tools, trainer, benchmarks, fuzzers) |" \
  "|---|---|---|---|---|---|---|" "${rows[@]}")
if [ $write -eq 1 ]; then
  /usr/bin/python3 - "$table" <<'PY'
import re, sys
p = "boards/README.md"; s = open(p).read()
begin, end = "<!-- size-table:begin -->", "<!-- size-table:end -->"
new = begin + "\n" + sys.argv[1] + "\n" + end
s = re.sub(re.escape(begin) + ".*?" + re.escape(end), new, s, flags=re.S) if begin in s else s + "\n" + new + "\n"
open(p, "w").write(s)
PY
fi
echo "$table"
exit $failed
