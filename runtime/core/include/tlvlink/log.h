#pragma once
// Logging by category with levels, for library and daemon code (CLI front ends print their
// results to stdout themselves). libcamera's model, made small:
//   TLV_LOG_CATEGORY(kLogCapture, "capture");            // once, in one .cc file
//   TLV_LOG(kLogCapture, kWarning, "%s: reopened after %d ms", path, ms);
// - Levels per category from the environment, read once: TLVLINK_LOG_LEVELS="capture:debug,*:warn"
//   (names debug, info, warn, error, off; "*" sets the default). Default: info.
// - A compile-time floor, TLVLINK_LOG_MIN_LEVEL (0 debug .. 4 off; default 0, and no preset or
//   board sets it: pass -DTLVLINK_LOG_MIN_LEVEL=N to CMake): calls below it compile to nothing,
//   arguments unevaluated.
// - No heap: a line is formatted into a fixed buffer (kMaxLogLine, longer lines end in "...")
//   and written with one write(2), so lines of concurrent threads never interleave.
// - Output goes to stderr, or to a sink installed with set_log_sink (tests, the daemon).

#include <atomic>
#include <cstddef>
#include <cstdint>

#ifndef TLVLINK_LOG_MIN_LEVEL
#define TLVLINK_LOG_MIN_LEVEL 0
#endif

namespace tlvlink {

enum class LogLevel : uint8_t { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3, kOff = 4 };

const char* log_level_name(LogLevel level);  // "debug", "info", "warn", "error", "off"

// Whether calls at `level` are compiled in at all (TLVLINK_LOG_MIN_LEVEL).
constexpr bool log_compiled_in(LogLevel level, int min_level = TLVLINK_LOG_MIN_LEVEL) {
  return static_cast<int>(level) >= min_level;
}

// A named category; its level is resolved from TLVLINK_LOG_LEVELS at its first use.
class LogCategory {
 public:
  explicit constexpr LogCategory(const char* name) : name_(name) {}
  LogCategory(const LogCategory&) = delete;
  LogCategory& operator=(const LogCategory&) = delete;

  const char* name() const { return name_; }
  bool enabled(LogLevel level) const;
  void set_level(LogLevel level);  // overrides the environment (tests, --verbose flags)

 private:
  const char* name_;
  // -1: not resolved yet. Threads racing on the first use resolve the same value.
  mutable std::atomic<int8_t> level_{-1};
};

inline constexpr size_t kMaxLogLine = 512;

struct LogRecord {
  const LogCategory* category;
  LogLevel level;
  double monotonic_s;   // CLOCK_MONOTONIC seconds
  const char* message;  // without the trailing newline
};
// Where lines go. `sink` nullptr restores stderr. The sink is called on the logging thread.
using LogSink = void (*)(const LogRecord& record, void* context);
void set_log_sink(LogSink sink, void* context);

[[gnu::format(printf, 3, 4)]] void log_write(const LogCategory& category, LogLevel level,
                                             const char* format, ...);

}  // namespace tlvlink

#define TLV_LOG_CATEGORY(var, name) \
  ::tlvlink::LogCategory var { name }

#define TLV_LOG(category, level, ...)                                              \
  do {                                                                             \
    if constexpr (::tlvlink::log_compiled_in(::tlvlink::LogLevel::level)) {        \
      if ((category).enabled(::tlvlink::LogLevel::level))                          \
        ::tlvlink::log_write((category), ::tlvlink::LogLevel::level, __VA_ARGS__); \
    }                                                                              \
  } while (0)
