#!/usr/bin/env bash
# The boards part of the cross stage: tlvlinkd for every board (by way of the board packages of
# size_table.sh: the scenes' distinct option sets on rpi5-a76, every other ARM board with
# grasp-two-mini), the size table, and lintian on one package (errors fail, warnings print).
#   tools/boards/ci_boards.sh      (needs build/host's tlvlink: the host stage builds it)
set -uo pipefail
cd "$(dirname "$0")/../.."
t0=$(date +%s)
bash tools/boards/size_table.sh --write; rc=$?
deb=$(ls build/flash/rpi5-a76-grasp-two-mini/tlvlink_*_arm64.deb 2>/dev/null | head -1)
if [ -n "$deb" ]; then
  echo "lintian $deb:"
  lintian --no-tag-display-limit "$deb"; lrc=$?
  [ $lrc -eq 0 ] || { echo "ci_boards: lintian reported errors" >&2; rc=1; }
else
  echo "ci_boards: no rpi5-a76 package to check" >&2; rc=1
fi
echo "ci_boards: $(( $(date +%s) - t0 ))s"
exit $rc
