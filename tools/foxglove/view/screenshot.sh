#!/usr/bin/env bash
# The README's picture of the live view (tools/foxglove/README.md): the fake board streams two
# sensors at 60 fps, `tlvlink listen --foxglove` serves them, live.html (the Foxglove protocol in
# 100 lines of browser JavaScript) shows them in headless Chromium, and the DevTools protocol
# saves a PNG; it then reads the page: connected, a sensor with its gel and a head drawn (exit 1
# otherwise). Needs Debian's chromium and the npm `ws` package (tools/setup/install_npm_clients.sh).
# ctest foxglove.live_view runs it into the build tree (e2e; skipped, exit 77, without them).
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
# Exit 77 (ctest: skipped) without what it needs; otherwise 0 only when the page showed the stream.
command -v chromium >/dev/null || { echo "SKIP: Debian's chromium is not installed (install_deps.sh test)" >&2; exit 77; }
command -v node >/dev/null && [ -d "$npm_dir/node_modules/ws" ] ||
  { echo "SKIP: node or the npm ws package is absent (tools/setup/install_npm_clients.sh)" >&2; exit 77; }
# Images: a fixture JPEG with its contact mask after every 10th prediction (--images 10).
"$build/tools/listen/bench/tlvlink_stream_check" board --link "pty:$work/tty" --frames 3000 --rate 120 --hold 2 \
  --images 10 >/dev/null &
pids+=($!)
"$build/tools/cli/tlvlink" listen --serial "$work/tty" --duration 20 --foxglove 127.0.0.1:0 >/dev/null 2>"$work/listen.log" &
pids+=($!)
for _ in $(seq 100); do grep -q "foxglove: serving on" "$work/listen.log" && break; sleep 0.1; done
address=$(sed -n 's/^foxglove: serving on //p' "$work/listen.log")
[ -n "$address" ] || { echo "screenshot: tlvlink listen --foxglove did not start: $(cat "$work/listen.log")" >&2; exit 1; }
# Port 0: Chromium picks a free one and writes it to DevToolsActivePort (runs may overlap).
chromium --headless=new --no-sandbox --disable-gpu --remote-debugging-port=0 --user-data-dir="$work/chrome" \
  about:blank >/dev/null 2>&1 &
pids+=($!)
port=
for _ in $(seq 200); do
  port=$(head -n 1 "$work/chrome/DevToolsActivePort" 2>/dev/null || true)
  [ -n "$port" ] && break
  sleep 0.1
done
[ -n "$port" ] || { echo "screenshot: chromium did not open its DevTools port" >&2; exit 1; }
NODE_PATH="$npm_dir/node_modules" node "$here/screenshot.js" "$port" "file://$here/live.html?ws=$address" "$out" 4
