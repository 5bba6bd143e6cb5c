#include "line_io.h"

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace tlvlink::datasets {

Status LineReader::open(const std::string& path) {
  path_ = path;
  line_number_ = 0;
  in_.close();
  in_.clear();
  in_.open(path, std::ios::binary);
  TLV_ENSURE(in_.is_open(), ErrorCode::kIo, "%s: cannot open: %s", path.c_str(),
             std::strerror(errno));
  return {};
}

bool LineReader::next(std::string& line) {
  if (!std::getline(in_, line)) return false;
  ++line_number_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

Status LineWriter::open(const std::string& path) {
  path_ = path;
  bytes_ = 0;
  file_.reset(std::fopen(path.c_str(), "wb"));
  TLV_ENSURE(file_ != nullptr, ErrorCode::kIo, "%s: cannot create: %s", path.c_str(),
             std::strerror(errno));
  return {};
}

Status LineWriter::write_line(std::string_view line) {
  TLV_ENSURE(file_ != nullptr, ErrorCode::kInvalidState, "%s: written after close", path_.c_str());
  const bool ok = std::fwrite(line.data(), 1, line.size(), file_.get()) == line.size() &&
                  std::fputc('\n', file_.get()) != EOF;
  TLV_ENSURE(ok, ErrorCode::kIo, "%s: write failed: %s", path_.c_str(), std::strerror(errno));
  bytes_ += static_cast<int64_t>(line.size()) + 1;
  return {};
}

Status LineWriter::close() {
  if (!file_) return {};
  TLV_ENSURE(std::fclose(file_.release()) == 0, ErrorCode::kIo, "%s: close failed: %s",
             path_.c_str(), std::strerror(errno));
  return {};
}

bool is_blank(std::string_view line) {
  return trim(line).empty();
}

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
