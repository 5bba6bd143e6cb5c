#!/usr/bin/env bash
# Builds a private arm64 sysroot from Debian's arm64 packages, without installing any arm64
# package into the system (installing libxnnpack-dev:arm64 would remove the amd64 XNNPACK).
#   make_sysroot.sh [SYSROOT_DIR]
# Default SYSROOT_DIR: ${XDG_CACHE_HOME:-$HOME/.cache}/tlvlink/sysroot-arm64
# .deb cache: $TLVLINK_DEB_CACHE, default ${XDG_CACHE_HOME:-$HOME/.cache}/tlvlink/arm64-debs
# The arm64 libc/libstdc++ come from the cross toolchain (/usr/aarch64-linux-gnu), not from here.
# Idempotent: a stamp file records the exact package versions; a matching stamp means no work.
# Quiet on success; prints the reason and exits non-zero on failure.
set -euo pipefail

cache_root=${XDG_CACHE_HOME:-$HOME/.cache}/tlvlink
sysroot=${1:-$cache_root/sysroot-arm64}
deb_cache=${TLVLINK_DEB_CACHE:-$cache_root/arm64-debs}
stamp=$sysroot/.tlvlink-sysroot-stamp
SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo

# Runtime (XNNPACK stack, flatbuffers, libsodium: the model file's hash and signatures), tests
# (GoogleTest, static arm64 libs in libgtest-dev), libusb (the USB stream's host side, built into
# the boards' test programs: the emulated board runs both ends of the USB link; libusb-1.0.so.0
# needs libudev.so.1), and the arch-independent headers the host tools need when they are
# cross-built too.
# Not flatbuffers-compiler-dev: its FlatcTargets.cmake names an arm64 flatc that is not here,
# and code generation uses the host's /usr/bin/flatc anyway.
packages=(libxnnpack-dev libxnnpack0 libpthreadpool-dev libpthreadpool0 libcpuinfo-dev libcpuinfo0
  libflatbuffers-dev libflatbuffers2 libgtest-dev libgmock-dev libcli11-dev nlohmann-json3-dev
  libturbojpeg0-dev libturbojpeg0 libjpeg62-turbo-dev libjpeg62-turbo libtomlplusplus-dev
  libusb-1.0-0-dev libusb-1.0-0 libudev1 libsodium-dev libsodium23)

die() { echo "make_sysroot: $*" >&2; exit 1; }

command -v dpkg-deb >/dev/null || die "dpkg-deb not found (this script needs a Debian-based host)"

# 1. The arm64 architecture and its package lists (apt-get update only if the lists are missing).
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  $SUDO dpkg --add-architecture arm64 || die "dpkg --add-architecture arm64 failed"
fi
if ! ls /var/lib/apt/lists/*_binary-arm64_Packages* >/dev/null 2>&1; then
  $SUDO apt-get update -qq >/dev/null || die "apt-get update failed (no network or mirror?)"
fi

# 2. Resolve exact versions (one apt-cache call: each call costs ~1 s). Arch-independent
#    packages have no candidate as pkg:arm64 and resolve under their plain name.
declare -A candidate=()
query=()
for p in "${packages[@]}"; do query+=("$p:arm64" "$p"); done
while read -r name version; do
  candidate[$name]=$version
done < <(apt-cache policy "${query[@]}" 2>/dev/null |
         awk '/^[^ ].*:$/ {name=substr($0, 1, length($0)-1)} /^  Candidate:/ {print name, $2}')
specs=()
for p in "${packages[@]}"; do
  if [ "${candidate[$p:arm64]:-(none)}" != "(none)" ]; then
    specs+=("$p:arm64=${candidate[$p:arm64]}")
  elif [ "${candidate[$p]:-(none)}" != "(none)" ]; then
    specs+=("$p=${candidate[$p]}")
  else
    die "no arm64 candidate for package '$p' (see: apt-cache policy $p:arm64)"
  fi
done
want_stamp=$(printf '%s\n' "${specs[@]}")

if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want_stamp" ]; then
  exit 0  # Up to date.
fi

# 3. Download the .debs into the cache (only those not already there).
mkdir -p "$deb_cache"
to_fetch=()
for spec in "${specs[@]}"; do
  name=${spec%%=*}; version=${spec#*=}
  pkg=${name%%:*}
  # apt-get download names files pkg_version-with-colon-escaped_arch.deb.
  file_version=${version//:/%3a}
  compgen -G "$deb_cache/${pkg}_${file_version}_*.deb" >/dev/null || to_fetch+=("$spec")
done
if [ ${#to_fetch[@]} -gt 0 ]; then
  apt_opts=(-qq)
  # As root, apt drops to the _apt user, which usually cannot write the cache dir.
  [ "$(id -u)" = 0 ] && apt_opts+=(-o APT::Sandbox::User=root)
  (cd "$deb_cache" && apt-get download "${apt_opts[@]}" "${to_fetch[@]}" >/dev/null) \
    || die "apt-get download failed for: ${to_fetch[*]}"
fi

# 4. Extract into a fresh sysroot (a stale one may hold files of older versions). Refuse to
#    replace a non-empty directory this script did not make.
if [ -d "$sysroot" ] && [ ! -f "$stamp" ] && [ -n "$(ls -A "$sysroot")" ]; then
  die "$sysroot exists, is not empty and has no stamp file: not replacing it"
fi
mkdir -p "$(dirname "$sysroot")"
tmp=$(mktemp -d "${sysroot%/}.tmp.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
for spec in "${specs[@]}"; do
  name=${spec%%=*}; version=${spec#*=}
  pkg=${name%%:*}
  deb=$(compgen -G "$deb_cache/${pkg}_${version//:/%3a}_*.deb" | head -n1)
  [ -n "$deb" ] || die "downloaded .deb for $spec not found in $deb_cache"
  arch=$(dpkg-deb -f "$deb" Architecture)
  [ "$arch" = arm64 ] || [ "$arch" = all ] || die "$deb is for '$arch', not arm64"
  dpkg-deb -x "$deb" "$tmp" || die "dpkg-deb -x $deb failed"
done

# 5. Absolute symlinks (e.g. lib*.so -> /usr/lib/...) would point into the host: make them
#    relative links inside the sysroot.
while IFS= read -r -d '' link; do
  target=$(readlink "$link")
  case "$target" in
    /*) ln -sfr "$tmp$target" "$link" ;;
  esac
done < <(find "$tmp" -type l -print0)

# 6. Sanity check: the libraries the toolchain file expects.
libdir=$tmp/usr/lib/aarch64-linux-gnu
for f in "$libdir/libXNNPACK.so" "$libdir/libpthreadpool.so" "$libdir/libcpuinfo.so" \
         "$libdir/libgtest.a" "$libdir/cmake/flatbuffers/FlatBuffersConfig.cmake" \
         "$libdir/pkgconfig/libusb-1.0.pc" "$libdir/libudev.so.1" "$libdir/libsodium.so" \
         "$tmp/usr/include/xnnpack.h" "$tmp/usr/include/sodium.h"; do
  [ -e "$f" ] || die "expected ${f#"$tmp"} in the sysroot, not found (package layout changed?)"
done

printf '%s\n' "$want_stamp" >"$tmp/.tlvlink-sysroot-stamp"
rm -rf "$sysroot"
mv "$tmp" "$sysroot"
trap - EXIT
