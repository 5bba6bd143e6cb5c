#include "tlvlink/log.h"

#include <unistd.h>

#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "tlvlink/clock.h"

namespace tlvlink {
namespace {

constexpr LogLevel kDefaultLevel = LogLevel::kInfo;

std::atomic<LogSink> g_sink{nullptr};
std::atomic<void*> g_sink_context{nullptr};

bool parse_level(const char* s, size_t n, LogLevel& out) {
  const struct {
    const char* name;
    LogLevel level;
  } names[] = {{"debug", LogLevel::kDebug},  {"info", LogLevel::kInfo},
               {"warn", LogLevel::kWarning}, {"warning", LogLevel::kWarning},
               {"error", LogLevel::kError},  {"off", LogLevel::kOff}};
  for (const auto& e : names) {
    if (std::strlen(e.name) == n && std::strncmp(e.name, s, n) == 0) {
      out = e.level;
      return true;
    }
  }
  return false;
}

// The level TLVLINK_LOG_LEVELS gives `category` ("name:level" pairs, "*" the default). Malformed
// entries are ignored: a typo in a debugging variable must not stop a daemon.
LogLevel level_from_env(const char* category) {
  const char* spec = std::getenv("TLVLINK_LOG_LEVELS");
  LogLevel fallback = kDefaultLevel, own = LogLevel::kOff;
  bool has_own = false;
  for (const char* p = spec; p != nullptr && *p != '\0';) {
    const char* end = std::strchr(p, ',');
    const size_t len = end != nullptr ? static_cast<size_t>(end - p) : std::strlen(p);
    const char* colon = static_cast<const char*>(std::memchr(p, ':', len));
    if (colon != nullptr) {
      const size_t name_len = static_cast<size_t>(colon - p);
      LogLevel level;
      if (parse_level(colon + 1, len - name_len - 1, level)) {
        if (name_len == 1 && *p == '*') fallback = level;
        if (std::strlen(category) == name_len && std::strncmp(category, p, name_len) == 0) {
          own = level;
          has_own = true;
        }
      }
    }
    p = end != nullptr ? end + 1 : nullptr;
  }
  return has_own ? own : fallback;
}

double monotonic_seconds() { return static_cast<double>(board_clock_ns()) * 1e-9; }

}  // namespace

const char* log_level_name(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "debug";
    case LogLevel::kInfo: return "info";
    case LogLevel::kWarning: return "warn";
    case LogLevel::kError: return "error";
    case LogLevel::kOff: return "off";
  }
  return "?";
}

bool LogCategory::enabled(LogLevel level) const {
  int8_t threshold = level_.load(std::memory_order_relaxed);
  if (threshold < 0) {
    threshold = static_cast<int8_t>(level_from_env(name_));
    level_.store(threshold, std::memory_order_relaxed);
  }
  return level != LogLevel::kOff && static_cast<int8_t>(level) >= threshold;
}

void LogCategory::set_level(LogLevel level) {
  level_.store(static_cast<int8_t>(level), std::memory_order_relaxed);
}

void set_log_sink(LogSink sink, void* context) {
  g_sink_context.store(context);
  g_sink.store(sink);
}

void log_write(const LogCategory& category, LogLevel level, const char* format, ...) {
  char message[kMaxLogLine];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(message, sizeof message, format, args);
  va_end(args);
  if (n >= static_cast<int>(sizeof message)) std::memcpy(message + sizeof message - 4, "...", 4);
  const double now = monotonic_seconds();
  if (LogSink sink = g_sink.load()) {
    sink(LogRecord{&category, level, now, message}, g_sink_context.load());
    return;
  }
  char line[kMaxLogLine + 64];
  int len = std::snprintf(line, sizeof line, "[%.3f] %s %s: %s\n", now, log_level_name(level),
                          category.name(), message);
  if (len < 0) return;
  if (len >= static_cast<int>(sizeof line)) len = static_cast<int>(sizeof line) - 1;
  // One write per line: lines from concurrent threads do not interleave. A failed write to
  // stderr has nowhere to be reported.
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line, static_cast<size_t>(len));
}

}  // namespace tlvlink
