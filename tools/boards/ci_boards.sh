#!/usr/bin/env bash
# The boards part of the board stage (run_tests.sh board, after board_test.sh): every board's
# package built by `tlvlink flash` and checked.
#   1. size_table.sh: every ARM board with grasp-two-mini and rpi5-a76 with every scene; the
#      table is printed with each row's growth against the committed one (boards/README.md);
#   2. lintian on every package built: errors fail, warnings are printed;
#   3. --install-to: the rpi5-a76 files written into an empty root filesystem, checked;
#   4. the emulated board: qemu-virt-a76's kernel + initramfs (the package's files) boot under
#      QEMU and run `tlvlinkd --verify` and `--check` on the A76's XNNPACK kernels.
# Needs build/host's tlvlink (the host stage builds it), the cross toolchain and sysroot, lintian
# and qemu-system-aarch64 (install_deps.sh rig).
#   ci_boards.sh --prebuild: only the compiler targets no other stage builds (jetson-orin-nano's
#   cortex-a78ae, rk3588's cortex-a76.cortex-a55), niced: run_tests.sh starts it beside the
#   emulated board's tests, whose waits leave the cores idle much of the time.
set -uo pipefail
cd "$(dirname "$0")/../.."
cli=${TLVLINK_CLI:-build/host/tools/cli/tlvlink}
t0=$(date +%s) rc=0
fail() { echo "ci_boards: FAIL: $*" >&2; rc=1; }
if [ "${1:-}" = --prebuild ]; then
  for b in jetson-orin-nano rk3588; do
    # The tree `tlvlink flash` uses for this -mcpu, configured first with line tables only (-g1,
    # as every tree of the test command): flash keeps the cache, and a stripped package is the
    # same either way (g++ does not let -g change the code it generates).
    cpu=$(sed -n 's/.*"TLVLINK_TARGET_CPU": "\([^"]*\)".*/\1/p' "boards/$b.json")
    nice -n 15 cmake --preset "$b" -B "build/flash/$cpu-build" -DTLVLINK_DEBUG_LINES=ON >/dev/null 2>&1 ||
      echo "ci_boards --prebuild: $b did not configure (the main run reports it)"
    nice -n 15 "$cli" flash --board "$b" --scene grasp-two-mini -o build/flash >/dev/null 2>&1 ||
      echo "ci_boards --prebuild: $b did not build (the main run reports it)"
  done
  echo "ci_boards --prebuild: $(( $(date +%s) - t0 ))s"
  exit 0
fi

bash tools/boards/size_table.sh || fail "a board package did not build (size table above)"

debs=(build/flash/*/tlvlink_*.deb)
[ -e "${debs[0]}" ] || fail "no package was built"
for deb in "${debs[@]}"; do
  [ -e "$deb" ] || continue
  out=$(lintian --tag-display-limit 0 "$deb" 2>&1 | grep -v "running with root privileges"); lrc=$?
  errors=$(echo "$out" | grep -c '^E:')
  warnings=$(echo "$out" | grep -c '^W:')
  echo "lintian ${deb#build/flash/}: $errors errors, $warnings warnings"
  [ -n "$out" ] && echo "$out" | sed 's/^/  /'
  [ "$errors" -eq 0 ] || fail "lintian errors in $deb"
done

sd=build/flash/sdcard-rpi5-a76
rm -rf "$sd" && mkdir -p "$sd"
if "$cli" flash --board rpi5-a76 --scene grasp-two-mini -o build/flash --install-to "$sd" >build/flash/install-to.log 2>&1; then
  for f in usr/bin/tlvlinkd etc/tlvlink/tlvlinkd.toml usr/share/tlvlink/models/grasp-two-mini.tlvm \
           lib/systemd/system/tlvlinkd.service usr/lib/sysusers.d/tlvlink.conf \
           etc/systemd/system/multi-user.target.wants/tlvlinkd.service; do
    [ -e "$sd/$f" ] || [ -L "$sd/$f" ] || fail "--install-to did not write /$f"
  done
  echo "install-to: $(find "$sd" -type f | wc -l) files, $(find "$sd" -type l | wc -l) unit links in $sd"
else
  tail -5 build/flash/install-to.log; fail "tlvlink flash --install-to"
fi

image=build/flash/qemu-virt-a76-grasp-two-mini/image
if [ -x "$image/boot.sh" ]; then
  tb=$(date +%s.%N)
  timeout 300 "$image/boot.sh" </dev/null >build/flash/qemu-virt-boot.log 2>&1
  grep -E '^RIG-(INIT|NOTE|PASS|FAIL|DONE)' build/flash/qemu-virt-boot.log | sed 's/^/  /'
  if grep -q '^RIG-DONE 0' build/flash/qemu-virt-boot.log && ! grep -q '^RIG-FAIL' build/flash/qemu-virt-boot.log; then
    echo "emulated board: booted the package's files and verified the model in $(awk -v a="$tb" -v b="$(date +%s.%N)" 'BEGIN {printf "%.1f", b - a}') s"
  else
    tail -40 build/flash/qemu-virt-boot.log; fail "the emulated board image did not verify"
  fi
else
  fail "no emulated board image ($image/boot.sh)"
fi
echo "ci_boards: $(( $(date +%s) - t0 ))s; $([ $rc -eq 0 ] && echo PASS || echo FAIL)"
exit $rc
