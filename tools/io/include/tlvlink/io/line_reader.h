#pragma once
// Reading line-oriented text files (dataset index and label files, JSON-lines) with bounded
// memory, counting lines for file:line messages.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::tools {

// Longest index line accepted; a longer one is reported as malformed (and skipped whole).
inline constexpr size_t kMaxLineBytes = size_t{1} << 20;

// Reads lines in 64 KiB chunks from a regular file (a FIFO or a directory is refused at open).
// Memory is bounded while reading: a line over kMaxLineBytes is not buffered whole; next()
// returns its first kMaxLineBytes + 1 bytes with too_long() set (so `line.size() >
// kMaxLineBytes` also tells) and skips the rest up to the next newline, so a 1.5 GB line costs
// 1 MiB, never 1.5 GB.
class LineReader {
 public:
  // kIo naming the path when the file cannot be opened or is not a regular file.
  Status open(const std::string& path);
  // Next line without its newline / trailing \r; false at the end of the file (or on a read
  // error: then error() says which).
  bool next(std::string& line);
  bool too_long() const { return too_long_; }  // the line next() returned was cut
  const Status& error() const { return error_; }
  int64_t line_number() const { return line_number_; }
  const std::string& path() const { return path_; }
  bool is_open() const { return file_.has_value(); }

 private:
  bool fill();  // refills buf_; false at the end or on error
  std::optional<RegularFile> file_;
  std::string path_;
  std::vector<char> buf_;
  size_t pos_ = 0, end_ = 0;
  bool too_long_ = false;
  Status error_;
  int64_t line_number_ = 0;
};

}  // namespace tlvlink::tools
