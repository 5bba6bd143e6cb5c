#!/bin/sh
# expect_exit.sh RC PATTERN COMMAND...: passes when COMMAND exits with RC and prints PATTERN.
rc_want=$1 pattern=$2
shift 2
out=$("$@" 2>&1)
rc=$?
echo "$out"
[ "$rc" -eq "$rc_want" ] || { echo "expect_exit: exit code $rc, expected $rc_want" >&2; exit 1; }
echo "$out" | grep -q -- "$pattern" || { echo "expect_exit: output lacks '$pattern'" >&2; exit 1; }
