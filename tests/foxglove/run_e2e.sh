#!/bin/sh
# The real Foxglove clients against tlvlink (ctest label e2e):
#   run_e2e.sh mcap|ws TLVLINK STREAM_CHECK WORKDIR
# Needs node and the npm packages pinned in package.json here, installed outside the tree by
# tools/setup/install_npm_clients.sh (into $TLVLINK_NPM_DIR, else ~/.cache/tlvlink/npm).
# Without them: exit 77, which ctest reports as skipped, with the reason on stderr.
set -eu
case_=$1 tlvlink=$2 check=$3 work=$4
npm_dir=${TLVLINK_NPM_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/tlvlink/npm}
if ! command -v node >/dev/null 2>&1; then
  echo "SKIP: node is not installed (tools/setup/install_deps.sh npm)" >&2
  exit 77
fi
for p in @mcap/core @foxglove/ws-protocol ws; do
  if [ ! -d "$npm_dir/node_modules/$p" ]; then
    echo "SKIP: the npm package $p is not installed in $npm_dir (tools/setup/install_npm_clients.sh)" >&2
    exit 77
  fi
done
rm -rf "$work"
mkdir -p "$work"
NODE_PATH="$npm_dir/node_modules" exec node "$(dirname "$0")/e2e_$case_.js" "$tlvlink" "$check" "$work"
