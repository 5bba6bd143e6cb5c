#include "toml_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace tlvlink::daemon::internal {
namespace {

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    default: return "a date/time";
  }
}

}  // namespace

Result<std::string> read_toml_file(const std::string& path, const char* what) {
  constexpr size_t kMaxBytes = 1 << 20;  // a configuration or scene is a few hundred bytes
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  TLV_ENSURE(fd >= 0, ErrorCode::kIo, "%s: cannot open the %s: %s", path.c_str(), what,
             std::strerror(errno));
  struct stat st {};
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  if (!regular || static_cast<size_t>(st.st_size) > kMaxBytes) {
    ::close(fd);
    return Error::make(ErrorCode::kInvalidArgument, "%s: %s", path.c_str(),
                       regular ? "larger than 1 MiB: not a TOML file" : "not a regular file");
  }
  std::string text(static_cast<size_t>(st.st_size), '\0');
  const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
  ::close(fd);
  TLV_ENSURE(n == static_cast<ssize_t>(text.size()), ErrorCode::kIo, "%s: read failed",
             path.c_str());
  return text;
}

TableReader::TableReader(const toml::table& table, std::string file, std::string prefix)
    : table_(table), file_(std::move(file)), prefix_(std::move(prefix)) {}

std::string TableReader::where(const char* key) const {
  const toml::node* n = table_.get(key);
  const auto line = n != nullptr ? n->source().begin.line : table_.source().begin.line;
  return file_ + ":" + std::to_string(line) + ": " + prefix_ + (prefix_.empty() ? "" : ".") + key;
}

std::string TableReader::child(const char* key, int index) const {
  std::string p = prefix_ + (prefix_.empty() ? "" : ".") + key;
  if (index >= 0) p += "[" + std::to_string(index) + "]";
  return p;
}

const toml::node* TableReader::find(const char* key) {
  read_.insert(key);
  return table_.get(key);
}

Status TableReader::text(const char* key, std::string& out) {
  const toml::node* n = find(key);
  if (n == nullptr) return {};
  TLV_ENSURE(n->is_string(), ErrorCode::kInvalidArgument, "%s: expected a string, got %s",
             where(key).c_str(), type_name(*n));
  out = *n->value<std::string>();
  return {};
}

Status TableReader::flag(const char* key, bool& out) {
  const toml::node* n = find(key);
  if (n == nullptr) return {};
  TLV_ENSURE(n->is_boolean(), ErrorCode::kInvalidArgument, "%s: expected true or false, got %s",
             where(key).c_str(), type_name(*n));
  out = *n->value<bool>();
  return {};
}

Status TableReader::integer(const char* key, int64_t& out, int64_t lo, int64_t hi) {
  const toml::node* n = find(key);
  if (n == nullptr) return {};
  TLV_ENSURE(n->is_integer(), ErrorCode::kInvalidArgument, "%s: expected an integer, got %s",
             where(key).c_str(), type_name(*n));
  const int64_t v = *n->value<int64_t>();
  TLV_ENSURE(v >= lo && v <= hi, ErrorCode::kInvalidArgument, "%s: %lld outside [%lld, %lld]",
             where(key).c_str(), static_cast<long long>(v), static_cast<long long>(lo),
             static_cast<long long>(hi));
  out = v;
  return {};
}

Status TableReader::integer32(const char* key, int32_t& out, int32_t lo, int32_t hi) {
  int64_t v = out;
  TLV_TRY(integer(key, v, lo, hi));
  out = static_cast<int32_t>(v);
  return {};
}

Status TableReader::number(const char* key, double& out, double lo, double hi) {
  const toml::node* n = find(key);
  if (n == nullptr) return {};
  TLV_ENSURE(n->is_number(), ErrorCode::kInvalidArgument, "%s: expected a number, got %s",
             where(key).c_str(), type_name(*n));
  const double v = *n->value<double>();
  TLV_ENSURE(std::isfinite(v) && v >= lo && v <= hi, ErrorCode::kInvalidArgument,
             "%s: %g outside [%g, %g]", where(key).c_str(), v, lo, hi);
  out = v;
  return {};
}

Status TableReader::number32(const char* key, float& out, float lo, float hi) {
  double v = out;
  TLV_TRY(number(key, v, lo, hi));
  out = static_cast<float>(v);
  return {};
}

Status TableReader::texts(const char* key, std::vector<std::string>& out) {
  const toml::node* n = find(key);
  if (n == nullptr) return {};
  const toml::array* a = n->as_array();
  TLV_ENSURE(a != nullptr, ErrorCode::kInvalidArgument, "%s: expected an array of strings, got %s",
             where(key).c_str(), type_name(*n));
  out.clear();
  for (const toml::node& e : *a) {
    TLV_ENSURE(e.is_string(), ErrorCode::kInvalidArgument,
               "%s: expected an array of strings, found %s", where(key).c_str(), type_name(e));
    out.push_back(*e.value<std::string>());
  }
  return {};
}

Status TableReader::choice(const char* key, std::initializer_list<const char*> choices,
                           int32_t& out) {
  std::string v;
  const bool present = has(key);
  TLV_TRY(text(key, v));
  if (!present) return {};
  int32_t i = 0;
  std::string all;
  for (const char* c : choices) {
    if (v == c) {
      out = i;
      return {};
    }
    all += (all.empty() ? "" : ", ") + std::string(c);
    ++i;
  }
  return Error::make(ErrorCode::kInvalidArgument, "%s: '%s' is not one of %s", where(key).c_str(),
                     v.c_str(), all.c_str());
}

Result<const toml::table*> TableReader::table(const char* key) {
  const toml::node* n = find(key);
  if (n == nullptr) return static_cast<const toml::table*>(nullptr);
  TLV_ENSURE(n->is_table(), ErrorCode::kInvalidArgument, "%s: expected a table, got %s",
             where(key).c_str(), type_name(*n));
  return n->as_table();
}

Result<const toml::array*> TableReader::array_of_tables(const char* key) {
  const toml::node* n = find(key);
  if (n == nullptr) return static_cast<const toml::array*>(nullptr);
  TLV_ENSURE(n->is_array_of_tables(), ErrorCode::kInvalidArgument,
             "%s: expected [[%s]] tables, got %s", where(key).c_str(), key, type_name(*n));
  return n->as_array();
}

Status TableReader::finish() const {
  for (const auto& [key, node] : table_) {
    if (read_.count(key.str()) != 0) continue;
    const std::string k(key.str());
    return Error::make(ErrorCode::kInvalidArgument, "%s:%u: %s%s%s: unknown key", file_.c_str(),
                       node.source().begin.line, prefix_.c_str(), prefix_.empty() ? "" : ".",
                       k.c_str());
  }
  return {};
}

}  // namespace tlvlink::daemon::internal
