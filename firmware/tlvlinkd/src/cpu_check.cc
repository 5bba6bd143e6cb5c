// tlvlinkd refuses to run on a CPU without the features its build needs (TLVLINK_TARGET_FEATURES,
// from the board definition), with a message naming them, instead of dying with SIGILL in the
// first A76 instruction. Debian's package checks in preinst; this covers a binary copied by hand
// or a root filesystem written with `tlvlink flash --install-to`.
//
// This file is compiled for plain armv8-a (-mcpu=generic, CMakeLists.txt) and runs as a
// constructor before any other static initialisation of the program, so nothing built for the
// target CPU has run yet.
#include <sys/auxv.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#if defined(__aarch64__)
#include <asm/hwcap.h>
#endif

#ifndef TLVLINK_TARGET_FEATURES
#define TLVLINK_TARGET_FEATURES ""
#endif
#ifndef TLVLINK_BOARD_NAME
#define TLVLINK_BOARD_NAME "?"
#endif

namespace {

#if defined(__aarch64__)
struct Feature {
  const char* name;  // as /proc/cpuinfo lists it
  unsigned long bit;
};
constexpr Feature kFeatures[] = {
    {"fp", HWCAP_FP},
    {"asimd", HWCAP_ASIMD},
    {"crc32", HWCAP_CRC32},
    {"atomics", HWCAP_ATOMICS},
    {"fphp", HWCAP_FPHP},
    {"asimdhp", HWCAP_ASIMDHP},
    {"asimdrdm", HWCAP_ASIMDRDM},
    {"lrcpc", HWCAP_LRCPC},
    {"asimddp", HWCAP_ASIMDDP},
};

// Writes with write(2) only: stdio may not be usable this early in every libc.
void say(const char* s) { (void)!::write(2, s, std::strlen(s)); }

__attribute__((constructor(101))) void check_cpu_features() {
  const unsigned long have = ::getauxval(AT_HWCAP);
  char missing[256] = "";
  const char* p = TLVLINK_TARGET_FEATURES;
  while (*p != '\0') {
    while (*p == ' ') ++p;
    const char* end = p;
    while (*end != '\0' && *end != ' ') ++end;
    const size_t n = static_cast<size_t>(end - p);
    for (const Feature& f : kFeatures) {
      if (n > 0 && std::strlen(f.name) == n && std::strncmp(f.name, p, n) == 0 &&
          (have & f.bit) == 0 && std::strlen(missing) + n + 2 < sizeof missing) {
        std::strcat(missing, " ");
        std::strncat(missing, p, n);
      }
    }
    p = end;
  }
  if (missing[0] == '\0') return;
  say("tlvlinkd: this binary is built for board " TLVLINK_BOARD_NAME
      " (CPU features: " TLVLINK_TARGET_FEATURES "); this CPU lacks");
  say(missing);
  say(". Install the build for this board (tlvlink flash --board NAME).\n");
  ::_exit(1);
}
#endif

}  // namespace
