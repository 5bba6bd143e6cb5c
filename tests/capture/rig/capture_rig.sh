# Board-rig test script (tools/rig): runs inside the emulated arm64 board with rig.sh's helpers.
# vivid is loaded with one capture node (inputs webcam, TV, S-Video, HDMI) and one output node;
# the README's capture_probe example runs first, then every GoogleTest case of the capture
# programs becomes one rig test.
rig_run capture.vivid_load 30 rig_vivid_load
rig_run capture.probe 60 sh -c 'capture_probe --list &&
  capture_probe "$(rig rig_vivid_node cap)" yuyv 640x360 --fps 25 --frames 50 --warmup 3 \
    --controls "osd_text_mode=2, brightness=100" | sed "s/^/note: /"'
rig_gtest /bin/capture_vivid_test 120
rig_gtest /bin/capture_unit_test 60
