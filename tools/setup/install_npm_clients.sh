#!/usr/bin/env bash
# Installs the real Foxglove clients the e2e tests of tests/foxglove run against tlvlink
# (@foxglove/ws-protocol with ws, @mcap/core: the versions pinned in tests/foxglove/package.json
# and package-lock.json) with `npm ci`, into a directory outside the source tree:
#   install_npm_clients.sh [DIR]     default: $TLVLINK_NPM_DIR, else ~/.cache/tlvlink/npm
# The tests look there (the same default); node_modules is never in the tree.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
dir=${1:-${TLVLINK_NPM_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/tlvlink/npm}}
command -v npm >/dev/null || { echo "install_npm_clients: npm not found (install_deps.sh npm installs nodejs and npm)" >&2; exit 1; }
mkdir -p "$dir"
# Already installed from this very lock file: nothing to do.
if [ -f "$dir/package-lock.json" ] && cmp -s "$dir/package-lock.json" "$here/tests/foxglove/package-lock.json" &&
   [ -d "$dir/node_modules/@mcap/core" ] && [ -d "$dir/node_modules/@foxglove/ws-protocol" ] && [ -d "$dir/node_modules/ws" ]; then
  echo "install_npm_clients: $dir is up to date"
  exit 0
fi
cp "$here/tests/foxglove/package.json" "$here/tests/foxglove/package-lock.json" "$dir/"
(cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
echo "install_npm_clients: installed into $dir"
