#!/usr/bin/env bash
# The C++ sources in the repository's one format (.clang-format: Google style with tlvlink's
# differences), with Debian's clang-format-14 (the `clang` package of install_deps.sh test).
#   tools/setup/format.sh            reformat every .cc/.h in place
#   tools/setup/format.sh --check    list the files that differ; exit 1 if any (ctest layout.format)
# Files: runtime/ firmware/ quantize/ tools/ tests/ (build outputs and fetched code excluded).
set -euo pipefail
cd "$(dirname "$0")/../.."
check=0
case "${1:-}" in --check) check=1 ;; "") ;; *) echo "usage: format.sh [--check]" >&2; exit 2 ;; esac
cf=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$cf" ]; then
  echo "format.sh: clang-format not found (install_deps.sh test installs clang)" >&2
  exit 77  # ctest: skipped
fi
mapfile -t files < <(find runtime firmware quantize tools tests -type f \( -name '*.cc' -o -name '*.h' \) \
  -not -path '*/build/*' -not -path '*/node_modules/*' | sort)
if [ "$check" -eq 0 ]; then
  printf '%s\0' "${files[@]}" | xargs -0 "$cf" -i --style=file
  echo "format.sh: ${#files[@]} files formatted"
  exit 0
fi
# One clang-format for all files: each differing file is named in its warnings.
mapfile -t bad < <("$cf" --style=file --dry-run "${files[@]}" 2>&1 |
  sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: \(warning\|error\): code should be clang-formatted.*/\1/p' | sort -u)
if [ ${#bad[@]} -gt 0 ]; then
  printf 'format.sh: not formatted (run tools/setup/format.sh): %s\n' "${bad[@]}" | head -40
  echo "format.sh: ${#bad[@]} of ${#files[@]} files differ from .clang-format"
  exit 1
fi
echo "format.sh: ${#files[@]} files formatted as .clang-format says"
