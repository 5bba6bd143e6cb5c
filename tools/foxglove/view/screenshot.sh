#!/usr/bin/env bash
# The README's picture of the live view (tools/foxglove/README.md): the fake board streams two
# sensors at 60 fps, `tlvlink listen --foxglove` serves them, live.html (the Foxglove protocol in
# 100 lines of browser JavaScript) shows them in headless Chromium, and the DevTools protocol
# saves a PNG. Needs Debian's chromium and the npm `ws` package (tools/setup/install_npm_clients.sh).
#   tools/foxglove/view/screenshot.sh [BUILD_DIR] [OUT.png]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build/host}
out=${2:-$here/live_view.png}
npm_dir=${TLVLINK_NPM_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/tlvlink/npm}
work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
"$build/tools/listen/bench/tlvlink_stream_check" board --link "pty:$work/tty" --frames 3000 --rate 120 --hold 2 >/dev/null &
pids+=($!)
"$build/tools/cli/tlvlink" listen --serial "$work/tty" --duration 20 --foxglove 127.0.0.1:0 >/dev/null 2>"$work/listen.log" &
pids+=($!)
for _ in $(seq 100); do grep -q "foxglove: serving on" "$work/listen.log" && break; sleep 0.1; done
address=$(sed -n 's/^foxglove: serving on //p' "$work/listen.log")
chromium --headless=new --no-sandbox --disable-gpu --remote-debugging-port=9333 --user-data-dir="$work/chrome" \
  about:blank >/dev/null 2>&1 &
pids+=($!)
for _ in $(seq 100); do curl -s http://127.0.0.1:9333/json/version >/dev/null 2>&1 && break; sleep 0.1; done
NODE_PATH="$npm_dir/node_modules" node "$here/screenshot.js" 9333 "file://$here/live.html?ws=$address" "$out" 4
