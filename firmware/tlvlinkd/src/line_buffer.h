#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "line_buffer.h is internal to firmware/tlvlinkd"
#endif
// A fixed buffer one output line is formatted into (no heap). A line that would not fit is
// reported (overflowed()) and not written: a limit is an error, never a silent truncation.

#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <string_view>

namespace tlvlink::daemon::internal {

class LineBuffer {
 public:
  static constexpr size_t kCapacity = 16384;

  void clear() {
    size_ = 0;
    overflow_ = false;
  }
  [[gnu::format(printf, 2, 3)]] void printf(const char* format, ...) {
    va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(data_ + size_, kCapacity - size_, format, args);
    va_end(args);
    if (n < 0 || static_cast<size_t>(n) >= kCapacity - size_) {
      overflow_ = true;
      return;
    }
    size_ += static_cast<size_t>(n);
  }
  // A JSON string with quotes, escaping what JSON requires.
  void json_string(std::string_view s) {
    put('"');
    for (char c : s) {
      if (c == '"' || c == '\\') {
        put('\\');
        put(c);
      } else if (static_cast<unsigned char>(c) < 0x20) {
        printf("\\u%04x", c);
      } else {
        put(c);
      }
    }
    put('"');
  }
  void put(char c) {
    if (size_ + 1 >= kCapacity) {
      overflow_ = true;
      return;
    }
    data_[size_++] = c;
  }
  std::string_view view() const { return {data_, size_}; }
  bool overflowed() const { return overflow_; }

 private:
  char data_[kCapacity];
  size_t size_ = 0;
  bool overflow_ = false;
};

}  // namespace tlvlink::daemon::internal
