# The rig's own test script (tools/rig/selftest.sh runs it): every facility later rig users rely
# on, checked in the guest; the host half checks what arrived.
rig_run rig.markers 10 true
rig_run rig.skip 10 sh -c 'echo "skips report their reason"; exit 77'
rig_run rig.port_out 10 sh -c 'seq 1 2000 | rig rig_send rig.data'
rig_run rig.share 10 sh -c 'test "$(cat /mnt/host/token)" = "$RIG_TOKEN" && echo "from the guest" >/mnt/host/from-guest'
rig_run rig.host_cmd 20 sh -c 'exec 3<>"$(rig rig_port rig.ctrl)" && read -r line <&3 && echo "pong $line" >&3'
rig_run rig.vivid_reload 30 sh -c 'rig rig_vivid_load && rig rig_vivid_node cap && rig rig_vivid_unload &&
  rig rig_vivid_load && rig rig_vivid_node out && rig rig_vivid_unload'
# USB: a CDC-ACM gadget on dummy_hcd, bytes board -> host, then unbind/rebind (an unplug/replug).
rig_run rig.usb_acm 30 sh -c '
  rig rig_usb_load && rig rig_gadget_acm g1 0x1d6b 0x0104 RIGSELFTEST dummy_udc.0 &&
  rig rig_wait_for /dev/ttyACM0 5 && test "$(cat /sys/bus/usb/devices/1-1/serial)" = RIGSELFTEST &&
  stty -F /dev/ttyGS0 raw -echo && rig rig_wait_raw /dev/ttyACM0 5 &&
  { timeout 5 head -c 11 /dev/ttyACM0 >/tmp/acm.got & } && sleep 0.2 && printf "hello board" >/dev/ttyGS0 &&
  wait && test "$(cat /tmp/acm.got)" = "hello board" &&
  rig rig_gadget_unbind g1 && sleep 0.5 && test ! -e /dev/ttyACM0 &&
  rig rig_gadget_bind g1 dummy_udc.0 && rig rig_wait_for /dev/ttyACM0 5 &&
  rig rig_gadget_remove g1'
