# Board-rig test script (tools/rig), sourced after tests/capture/rig/capture_rig.sh in the same
# boot (tools/setup/board_test.sh joins them): the prediction stream over USB in the emulated board,
# scenario by scenario (tests/listen/rig/stream_usb.sh: FunctionFS bulk <-> libusb and CDC-ACM
# /dev/ttyGS0 <-> /dev/ttyACM0 through dummy_hcd). Needs /bin/tlvlink_stream_check and, in
# /payload/stream/, stream_usb.sh and runtime/transport/scripts/usb_gadget.sh.
usb=/payload/stream/stream_usb.sh
rig_run usb.setup 60 sh $usb setup
for kind in ffs acm; do
  rig_run usb.$kind.stream 150 sh $usb stream $kind
  rig_run usb.$kind.replug 150 sh $usb replug $kind
  rig_run usb.$kind.reader_restart 150 sh $usb restart $kind
done
# Corruption injection: byte errors / drops between the board's Sender and the wire.
for rates in "1e-4 0" "1e-3 0" "1e-2 0" "0 1e-3" "1e-3 1e-3"; do
  set -- $rates
  rig_run "usb.ffs.corrupt.$1.$2" 150 sh $usb corrupt ffs $1 $2
done
rig_run usb.acm.corrupt.1e-3.1e-3 150 sh $usb corrupt acm 1e-3 1e-3
# Benchmarks (figures printed, not asserted): throughput over each link. Only when asked
# (tools/setup/board_test.sh --bench): the test command runs no benchmark.
if [ "${TLVLINK_RIG_BENCH:-0}" = 1 ]; then
  rig_run usb.ffs.bench 180 sh $usb bench ffs
  rig_run usb.acm.bench 180 sh $usb bench acm
fi
