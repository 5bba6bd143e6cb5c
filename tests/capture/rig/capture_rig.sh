# Board-rig test script (tools/rig): runs inside the emulated arm64 board with rig.sh's helpers.
# vivid is loaded with one capture node (inputs webcam, TV, S-Video, HDMI) and one output node;
# every GoogleTest case of the capture programs becomes one rig test.
rig_run capture.vivid_load 30 rig_vivid_load
rig_gtest /bin/capture_vivid_test 120
rig_gtest /bin/capture_unit_test 60
