#!/usr/bin/env bash
# Boots the rig with its own test script (selftest/guest.sh) and checks both halves: markers and
# skips, data out of the guest over virtio-serial, the 9p share, a host command talking to the
# guest over a port, vivid load/unload, and a USB CDC-ACM gadget with unbind/rebind.
#   tools/rig/selftest.sh [--cpu cortex-a72]      (extra arguments go to rig.py run)
set -uo pipefail
cd "$(dirname "$0")/../.."
py=${PYTHON:-/usr/bin/python3}
out=build/rig/selftest
share=$(mktemp -d /tmp/tlvrig-share.XXXXXX)
trap 'rm -rf "$share"' EXIT
token=$RANDOM$RANDOM
echo "$token" >"$share/token"
mkdir -p "$out"
rm -f "$out/ping.txt"
RIG_OUT=$out "$py" tools/rig/rig.py run --script tools/rig/selftest/guest.sh --share "$share" \
  --env RIG_TOKEN="$token" --host-port rig.ctrl --host-cmd "$py tools/rig/selftest/ping.py" \
  --out "$out" --timeout 180 "$@" | tee "$out/report.txt"
rc=${PIPESTATUS[0]}
check() {  # DESCRIPTION COMMAND...
  if "${@:2}"; then echo "selftest: ok   $1"; else echo "selftest: FAIL $1"; rc=1; fi
}
check "port rig.data carried 2000 lines" cmp -s "$out/rig.data.bin" <(seq 1 2000)
check "the guest wrote into the share" grep -qx "from the guest" "$share/from-guest"
check "the host command got its reply" grep -qx "pong ping" "$out/ping.txt"
check "the skipped test was reported skipped" grep -qE "SKIP +rig.skip +[0-9.]+s: skips report their reason" "$out/report.txt"
[ $rc -eq 0 ] && echo "selftest: PASS" || echo "selftest: FAIL"
exit $rc
