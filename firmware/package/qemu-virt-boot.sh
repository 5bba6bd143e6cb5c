# Start-up of the emulated board image (`tlvlink flash --board qemu-virt-a76`): run by the rig's
# /init (tools/rig) with its helpers loaded. It does what the Debian package does on a real board,
# without dpkg and systemd: the postinst's model check (`tlvlinkd --verify`: the golden pairs on
# this CPU's XNNPACK kernels, the scene's heads and sensors) and the configuration check of
# tlvlinkd.service's ExecStartPre. Their output is shown as notes on the console. The streaming
# run itself is the board stage's HIL test (tests/hil).
noted='out=$("$@" 2>&1); rc=$?; echo "$out" | sed "s/^/note: /"; exit $rc'
rig_run board.verify 300 sh -c "$noted" - tlvlinkd --config /etc/tlvlink/tlvlinkd.toml --verify
rig_run board.config 60 sh -c "$noted" - tlvlinkd --config /etc/tlvlink/tlvlinkd.toml --check
