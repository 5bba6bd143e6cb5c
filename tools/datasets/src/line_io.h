#pragma once
// Line-oriented text files of the dataset formats (label files, JSON-lines): a reader that
// counts lines for file:line messages and a writer that counts bytes and reports errors with
// the path. Internal to tlvlink_datasets.

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::datasets {

// Longest index line accepted; a longer one is reported as malformed (and skipped whole).
inline constexpr size_t kMaxLineBytes = size_t{1} << 20;

class LineReader {
 public:
  // kIo naming the path when the file cannot be opened.
  Status open(const std::string& path);
  // Next line without its newline / trailing \r; false at the end of the file.
  bool next(std::string& line);
  int64_t line_number() const { return line_number_; }
  const std::string& path() const { return path_; }
  bool is_open() const { return in_.is_open(); }

 private:
  std::ifstream in_;
  std::string path_;
  int64_t line_number_ = 0;
};

class LineWriter {
 public:
  Status open(const std::string& path);
  Status write_line(std::string_view line);  // appends '\n'
  Status close();
  bool is_open() const { return file_ != nullptr; }
  int64_t bytes() const { return bytes_; }

 private:
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Closer> file_;
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
