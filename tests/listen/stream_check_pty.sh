#!/bin/sh
# ctest: tlvlink_stream_check's board and host roles in two processes over a pty, as the
# emulated board runs them over CDC-ACM and the FunctionFS gadget. Exit status of the check.
#   stream_check_pty.sh PATH/TO/tlvlink_stream_check WORKDIR [EMULATOR ARGS...]
# (a cross build passes CMAKE_CROSSCOMPILING_EMULATOR, e.g. qemu-aarch64 -cpu cortex-a76 -L ...)
set -u
check=$1 dir=$2
shift 2
link=$dir/stream_check_tty
rm -f "$link"
"$@" "$check" board --link "pty:$link" --frames 400 --rate 200 --embedding --hold 3 >"$dir/stream_check_board.log" 2>&1 &
board=$!
i=0
while [ ! -e "$link" ] && [ $i -lt 300 ]; do sleep 0.01; i=$((i + 1)); done
"$@" "$check" check --source "serial:$link" --frames 400 --timeout 30
rc=$?
kill "$board" 2>/dev/null
wait "$board" 2>/dev/null
cat "$dir/stream_check_board.log"
exit $rc
