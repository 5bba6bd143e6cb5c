#pragma once
#ifndef TLVLINK_DATASETS_PRIVATE
#error "line_io.h is internal to tools/datasets: include its public headers instead"
#endif
// Line-oriented text files of the dataset formats (label files, JSON-lines): a reader that
// counts lines for file:line messages and a writer that counts bytes and reports errors with
// the path. Internal to tlvlink_datasets.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/atomic_file.h"
#include "tlvlink/error.h"
#include "tlvlink/io/line_reader.h"

namespace tlvlink::datasets {

// The bounded line reader is tools/io's (one reader for every line-oriented file).
using tools::kMaxLineBytes;
using tools::LineReader;

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
