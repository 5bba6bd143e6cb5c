# Board-rig test script (tools/rig) of the hardware-in-the-loop run (tests/hil/README.md): the
# set-up, the clean run and, unless HIL_FAULTS=0, the fault runs (HIL_RUNS: which), each one rig test. Needs
# tlvlinkd, tlvlink_hil_feeder and tlvlink_hil_relay in /bin, hil_guest.sh + usb_gadget.sh + the
# model in /payload/hil, the frames under /mnt/host (--share) and the port hil.jsonl (--port).
g=/payload/hil/hil_guest.sh
rig_run hil.setup 60 sh $g setup
rig_run hil.clean 300 sh $g clean
if [ "${HIL_FAULTS:-1}" = 1 ]; then
  for s in ${HIL_RUNS:-vivid_reload reader_restart garbage replug daemon_kill}; do
    rig_run "hil.$s" 180 sh $g $s
  done
fi
