#include "tlvlink/stream/line_buffer.h"

#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace tlvlink::stream {
namespace {

// The length of the UTF-8 sequence `lead` starts and the range of its first continuation byte
// (RFC 3629: no overlong forms, no surrogates, nothing above U+10FFFF); 0 = not a lead byte.
int utf8_length(unsigned char lead, unsigned char& low, unsigned char& high) {
  low = 0x80;
  high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) return 2;
  if (lead == 0xE0) low = 0xA0;
  if (lead == 0xED) high = 0x9F;
  if (lead >= 0xE0 && lead <= 0xEF) return 3;
  if (lead == 0xF0) low = 0x90;
  if (lead == 0xF4) high = 0x8F;
  if (lead >= 0xF0 && lead <= 0xF4) return 4;
  return 0;
}

}  // namespace

void LineBuffer::printf(const char* format, ...) {
  if (overflow_) return;
  va_list args;
  va_start(args, format);
  const size_t room = data_.size() - size_;
  const int n = std::vsnprintf(data_.data() + size_, room, format, args);
  va_end(args);
  if (n < 0 || static_cast<size_t>(n) >= room) {
    overflow_ = true;
    return;
  }
  size_ += static_cast<size_t>(n);
}

void LineBuffer::put(char c) {
  if (overflow_ || size_ + 1 >= data_.size()) {  // keeps room for a terminating NUL, as printf
    overflow_ = true;
    return;
  }
  data_[size_++] = c;
}

void LineBuffer::append(std::string_view s) {
  if (overflow_ || size_ + s.size() >= data_.size()) {
    overflow_ = true;
    return;
  }
  std::memcpy(data_.data() + size_, s.data(), s.size());
  size_ += s.size();
}

void LineBuffer::json_string(std::string_view s) {
  static constexpr std::string_view kReplacement = "\xEF\xBF\xBD";
  put('"');
  size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      switch (c) {
        case '"': append("\\\""); break;
        case '\\': append("\\\\"); break;
        case '\b': append("\\b"); break;
        case '\f': append("\\f"); break;
        case '\n': append("\\n"); break;
        case '\r': append("\\r"); break;
        case '\t': append("\\t"); break;
        default:
          if (c < 0x20) {
            printf("\\u%04x", c);
          } else {
            put(static_cast<char>(c));
          }
      }
      ++i;
      continue;
    }
    unsigned char low = 0, high = 0;
    const int length = utf8_length(c, low, high);
    if (length == 0) {  // not a lead byte
      append(kReplacement);
      ++i;
      continue;
    }
    // A sequence cut short: one replacement, and the byte that cut it is read again (it may
    // start a sequence of its own), as nlohmann::json's `replace` does.
    size_t j = i + 1;
    bool valid = true;
    for (int k = 1; k < length; ++k, ++j) {
      const auto b = j < s.size() ? static_cast<unsigned char>(s[j]) : 0;
      if (j >= s.size() || b < low || b > high) {
        valid = false;
        break;
      }
      low = 0x80;
      high = 0xBF;
    }
    append(valid ? s.substr(i, j - i) : kReplacement);
    i = j;
  }
  put('"');
}

void LineBuffer::json_number(float v) {
  if (!std::isfinite(v)) {
    append("null");
    return;
  }
  // The float as the double it widens to, in the shortest digits that read back as that double
  // (what nlohmann::json and Python print, so every reader gets the same number and the same
  // float again), laid out as nlohmann::json lays them out: plain decimals for exponents -4..15,
  // "1.5e+20" beyond.
  char sci[32];
  const std::to_chars_result r =
      std::to_chars(sci, sci + sizeof sci, static_cast<double>(v), std::chars_format::scientific);
  const std::string_view t(sci, static_cast<size_t>(r.ptr - sci));  // [-]d[.ddd]e(+|-)XX
  const size_t e = t.find('e');
  char digits[24];
  size_t k = 0;
  for (size_t i = 0; i < e; ++i) {
    if (t[i] >= '0' && t[i] <= '9') digits[k++] = t[i];
  }
  int exponent = 0;
  std::from_chars(t.data() + e + (t[e + 1] == '+' ? 2 : 1), t.data() + t.size(), exponent);
  const int n = exponent + 1;  // the value is 0.d1d2...dk * 10^n
  const int kk = static_cast<int>(k);
  const std::string_view d(digits, k);
  if (t[0] == '-') put('-');
  if (kk <= n && n <= 15) {  // 1234e7 -> 12340000000.0
    append(d);
    for (int i = kk; i < n; ++i) put('0');
    append(".0");
  } else if (0 < n && n <= 15) {  // 1234e-2 -> 12.34
    append(d.substr(0, static_cast<size_t>(n)));
    put('.');
    append(d.substr(static_cast<size_t>(n)));
  } else if (-4 < n && n <= 0) {  // 1234e-6 -> 0.001234
    append("0.");
    for (int i = n; i < 0; ++i) put('0');
    append(d);
  } else {  // 1.234e+20, 1e-07
    put(d[0]);
    if (k > 1) {
      put('.');
      append(d.substr(1));
    }
    printf("e%c%02d", n - 1 < 0 ? '-' : '+', n - 1 < 0 ? 1 - n : n - 1);
  }
}

void LineBuffer::key(const char* key) {
  put(',');
  put('"');
  append(key);
  append("\":");
}

}  // namespace tlvlink::stream
