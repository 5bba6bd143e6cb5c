#!/usr/bin/env bash
# Size table of the board packages (boards/README.md, between the size-table markers): for each
# board x scene, tlvlinkd's code and data (text+data), the runtime + daemon libraries (text+data), the stripped
# model, the .deb, and what the scene's build leaves out. Each row comes from `tlvlink flash`
# (build/host's CLI), which builds one tree per -mcpu and rebuilds only what a scene's options
# change.
#   tools/boards/size_table.sh [--all] [--write]
# Default (CI): every board with grasp-two-mini, and rpi5-a76 with every scene (8 packages;
# 4 compiler targets, two of them the cross stage's trees when present). --all: every board x scene (20). Each row is compared with the committed table:
# the last column says how much it grew or shrank, so growth is visible in every CI log.
# --write: replace the rows built in boards/README.md (the others stay as committed).
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
for b in "${arm_boards[@]}"; do
  for s in "${scenes[@]}"; do
    if [ $all -eq 1 ] || [ "$s" = grasp-two-mini ] || [ "$b" = rpi5-a76 ]; then pairs+=("$b $s"); fi
  done
done

# The cross stage's trees have the same compiler settings as these boards (generic-a76: -mcpu
# cortex-a76; rpi4-a72): when they exist (CI), the packages are built in them and only the
# daemon and the options a scene changes are recompiled. flash refuses a tree for another -mcpu.
reuse_tree() {
  case "$1" in
    rpi5-a76|qemu-virt-a76) [ -f build/generic-a76/CMakeCache.txt ] && echo build/generic-a76 ;;
    rpi4-a72) [ -f build/rpi4-a72/CMakeCache.txt ] && echo build/rpi4-a72 ;;
  esac
}
kb() { awk -v b="$1" 'BEGIN {printf "%.1f KB", b / 1024}'; }
# The committed row's tlvlinkd size in bytes (column 3, "N.N KB"), for the growth column.
committed() {
  awk -F'|' -v b=" $1 " -v s=" $2 " '$2 == b && $3 == s {gsub(/[^0-9.]/, "", $4); print $4 * 1024; exit}' boards/README.md
}
rows=() failed=0 t_all=$(date +%s)
for p in "${pairs[@]}"; do
  read -r board scene <<<"$p"
  out=build/flash/$board-$scene
  t0=$(date +%s)
  tree=$(reuse_tree "$board")
  if ! log=$("$cli" flash --board "$board" --scene "$scene" -o build/flash -j "$jobs" ${tree:+--build-dir "$tree"} 2>&1); then
    echo "$log" | tail -8 >&2
    rows+=("| $board | $scene | FAILED | | | | | |"); failed=1; continue
  fi
  # text+data: the file size moves in 64 KiB steps (the segments' alignment on arm64).
  daemon=$(aarch64-linux-gnu-size "$out/root/usr/bin/tlvlinkd" | awk 'END {print $1 + $2}')
  libs=0
  dir=$(echo "$log" | sed -n 's/^build tree: //p')
  # The archives on tlvlinkd's link line (a tree keeps the archives of earlier scenes' options).
  for a in $(ninja -C "$dir" -t commands firmware/tlvlinkd/tlvlinkd | tail -1 | tr ' ' '\n' |
             grep -E '^(runtime|firmware)/.*libtlvlink_[a-z_]*\.a$'); do
    libs=$(( libs + $(aarch64-linux-gnu-size -t "$dir/$a" | awk 'END {print $1 + $2}') ))
  done
  model=$(stat -c %s "$out/$scene.tlvm")
  deb=$(stat -c %s "$out"/tlvlink_*.deb)
  left=$(echo "$log" | awk '/^left out:/ {on = 1; next} /^kept without/ {on = 0} on' |
         sed 's/^ *//; s/ (.*//' | grep -v '^tests, host tools' | paste -sd ';' | sed 's/;/; /g')
  before=$(committed "$board" "$scene")
  growth="new"
  [ -n "$before" ] && growth=$(awk -v a="$daemon" -v b="$before" 'BEGIN {d = a - b; printf "%+.1f KB (%+.1f%%)", d / 1024, 100 * d / b}')
  rows+=("| $board | $scene | $(kb "$daemon") | $(kb "$libs") | $(kb "$model") | $(kb "$deb") | ${left:-—} | $growth |")
  echo "size_table: $board x $scene in $(( $(date +%s) - t0 ))s" >&2
done

header="| board | scene | tlvlinkd (text+data) | runtime + daemon libraries (text+data) | model (stripped) | .deb | left out (besides tests, host tools, trainer, benchmarks, fuzzers) | tlvlinkd vs the committed table |"
printf '%s\n' "$header" "|---|---|---|---|---|---|---|---|" "${rows[@]}"
echo "size_table: ${#pairs[@]} packages in $(( $(date +%s) - t_all ))s"
if [ $write -eq 1 ]; then
  /usr/bin/python3 - "$(printf '%s\n' "${rows[@]}")" "$header" <<'PY'
import re, sys
p = "boards/README.md"; s = open(p).read()
begin, end = "<!-- size-table:begin -->", "<!-- size-table:end -->"
old = {}
m = re.search(re.escape(begin) + "(.*?)" + re.escape(end), s, flags=re.S)
for line in (m.group(1) if m else "").splitlines():
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) >= 7 and cells[0] not in ("board", "---"):
        old[(cells[0], cells[1])] = "| " + " | ".join(cells[:7]) + " |"
for line in sys.argv[1].splitlines():
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    old[(cells[0], cells[1])] = "| " + " | ".join(cells[:7]) + " |"
header = "|".join(sys.argv[2].split("|")[:8]) + "|"
table = "\n".join([header, "|---|---|---|---|---|---|---|"] + [old[k] for k in sorted(old)])
new = begin + "\n" + table + "\n" + end
s = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: new, s, flags=re.S) if m else s + "\n" + new + "\n"
open(p, "w").write(s)
PY
fi
exit $failed
