#pragma once
// A buffer one output line is formatted into, over storage the caller owns (FixedLineBuffer owns
// a fixed array: no heap). A line that does not fit is reported (overflowed()) and must not be
// written: a limit is an error, never a silent truncation.

#include <array>
#include <cstddef>
#include <span>
#include <string_view>

namespace tlvlink::stream {

class LineBuffer {
 public:
  explicit LineBuffer(std::span<char> storage) : data_(storage) {}
  LineBuffer(const LineBuffer&) = delete;  // points into storage it may not own
  LineBuffer& operator=(const LineBuffer&) = delete;

  void clear() {
    size_ = 0;
    overflow_ = false;
  }
  [[gnu::format(printf, 2, 3)]] void printf(const char* format, ...);
  void put(char c);
  void append(std::string_view s);
  // A JSON string with quotes: escapes what JSON requires (as nlohmann::json does) and writes
  // each byte that is not valid UTF-8 as U+FFFD (a board's strings are not checked).
  void json_string(std::string_view s);
  // The float widened to double, in the shortest decimal that reads back as that double, laid
  // out as nlohmann::json does ("0.10000000149011612", "60.0", "3.000000060122632e+20"; Python
  // prints the same value); NaN and the infinities (which JSON has not) as null.
  void json_number(float v);
  // ,"key":  (a key after the first of an object).
  void key(const char* key);

  std::string_view view() const { return {data_.data(), size_}; }
  size_t capacity() const { return data_.size(); }
  bool overflowed() const { return overflow_; }

 private:
  std::span<char> data_;
  size_t size_ = 0;
  bool overflow_ = false;
};

// A LineBuffer with its storage inside (neither copyable nor movable).
template <size_t N>
class FixedLineBuffer : public LineBuffer {
 public:
  static constexpr size_t kCapacity = N;
  FixedLineBuffer() : LineBuffer(std::span<char>(storage_)) {}

 private:
  std::array<char, N> storage_;
};

}  // namespace tlvlink::stream
