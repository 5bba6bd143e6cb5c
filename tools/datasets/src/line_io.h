#pragma once
// Line-oriented text files of the dataset formats (label files, JSON-lines): a reader that
// counts lines for file:line messages and a writer that counts bytes and reports errors with
// the path. Internal to tlvlink_datasets.

#include <cstdint>
#include <memory>
#include <string>
#include <optional>
#include <string_view>
#include <vector>

#include "tlvlink/atomic_file.h"
#include "tlvlink/error.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::datasets {

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

// Writes an index file atomically (tlvlink/atomic_file.h): the lines go to a temporary that
// close() renames over the path; a writer dropped without close() leaves the old file as it was.
class LineWriter {
 public:
  Status open(const std::string& path);
  Status write_line(std::string_view line);  // appends '\n'
  Status close();
  bool is_open() const { return file_.has_value(); }
  int64_t bytes() const { return bytes_; }

 private:
  static constexpr size_t kFlushBytes = size_t{64} << 10;
  Status flush();
  std::optional<AtomicFile> file_;
  std::string pending_;  // lines not yet written (up to kFlushBytes)
  std::string path_;
  int64_t bytes_ = 0;
};

bool is_blank(std::string_view line);
std::string_view trim(std::string_view s);

// One path component of letters, digits, '_', '-', '.' (not "." or ".."): session folders,
// object names.
bool is_safe_name(std::string_view name);
// A relative path that stays inside the set: no leading '/', no empty, "." or ".." component.
// (Index entries of real sets may use any other characters.)
bool is_safe_relative_path(std::string_view path);

// Creates `dir` and its parents; kIo naming the directory on failure.
Status make_dirs(const std::string& dir);
std::string join_path(const std::string& a, std::string_view b);

}  // namespace tlvlink::datasets
