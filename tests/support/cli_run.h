#pragma once
// Runs a command-line tool the way a user does (through the shell) and keeps its exit code and
// output, for the end-to-end tests of the tlvlink CLIs.

#include <string>

#include <gtest/gtest.h>

namespace tlvlink::testing {

struct CliRun {
  int exit_code = -1;  // -1: could not start, or killed by a signal
  std::string out;     // stdout, and stderr unless dropped
};

enum class Stderr { kMerged, kDropped };

// `[emulator ]binary args`, e.g. emulator "qemu-aarch64 -L /sysroot" for a cross-built binary.
CliRun run_cli(const std::string& binary, const std::string& args,
               Stderr stderr_mode = Stderr::kMerged, const std::string& emulator = "");

#ifdef TLVLINK_CLI_BINARY
#ifndef TLVLINK_CLI_EMULATOR
#define TLVLINK_CLI_EMULATOR ""
#endif
// The `tlvlink` binary the including test target names (compile definitions TLVLINK_CLI_BINARY,
// and TLVLINK_CLI_EMULATOR for a cross-built one).
inline CliRun run_tlvlink(const std::string& args, Stderr stderr_mode = Stderr::kMerged) {
  return run_cli(TLVLINK_CLI_BINARY, args, stderr_mode, TLVLINK_CLI_EMULATOR);
}
#endif

}  // namespace tlvlink::testing

#define EXPECT_RUN(run, code) EXPECT_EQ((run).exit_code, code) << (run).out
#define ASSERT_RUN(run, code) ASSERT_EQ((run).exit_code, code) << (run).out
