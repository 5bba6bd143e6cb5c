#include "line_io.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace tlvlink::datasets {

Status LineWriter::open(const std::string& path) {
  path_ = path;
  bytes_ = 0;
  TLV_ASSIGN_OR_RETURN(AtomicFile f, AtomicFile::create(path.c_str()));
  file_.emplace(std::move(f));
  return {};
}

Status LineWriter::write_line(std::string_view line) {
  TLV_ENSURE(file_.has_value(), ErrorCode::kInvalidState, "%s: written after close", path_.c_str());
  pending_.append(line);
  pending_ += '\n';
  bytes_ += static_cast<int64_t>(line.size()) + 1;
  return pending_.size() >= kFlushBytes ? flush() : Status{};
}

Status LineWriter::flush() {
  Status s = file_->write(pending_.data(), pending_.size());
  pending_.clear();
  if (!s.ok()) file_.reset();  // AtomicFile removed the temporary; the old file stays
  return s;
}

Status LineWriter::close() {
  if (!file_) return {};
  TLV_TRY(flush());
  Status s = file_->commit();
  file_.reset();
  return s;
}

bool is_blank(std::string_view line) { return trim(line).empty(); }

std::string_view trim(std::string_view s) {
  const char* ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string_view::npos) return {};
  const size_t e = s.find_last_not_of(ws);
  return s.substr(b, e - b + 1);
}

bool is_safe_name(std::string_view name) {
  if (name.empty() || name == "." || name == ".." || name.size() > 255) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

bool is_safe_relative_path(std::string_view path) {
  if (path.empty() || path.size() > 4096) return false;
  size_t start = 0;
  for (;;) {
    const size_t slash = path.find('/', start);
    const std::string_view part = path.substr(
        start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
    if (part.empty() || part == "." || part == ".." || part.find('\0') != std::string_view::npos)
      return false;
    if (slash == std::string_view::npos) return true;
    start = slash + 1;
  }
}

Status make_dirs(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  TLV_ENSURE(!ec, ErrorCode::kIo, "cannot create directory '%s': %s", dir.c_str(),
             ec.message().c_str());
  return {};
}

std::string join_path(const std::string& a, std::string_view b) {
  std::string s = a;
  if (!s.empty() && s.back() != '/') s += '/';
  s += b;
  return s;
}

}  // namespace tlvlink::datasets
