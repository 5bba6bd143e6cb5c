#include "tlvlink/io/line_reader.h"

#include <algorithm>
#include <cstring>

namespace tlvlink::tools {

Status LineReader::open(const std::string& path) {
  path_ = path;
  line_number_ = 0;
  pos_ = end_ = 0;
  too_long_ = false;
  error_ = {};
  file_.reset();
  TLV_ASSIGN_OR_RETURN(RegularFile f, RegularFile::open(path.c_str()));
  file_.emplace(std::move(f));
  buf_.resize(size_t{64} << 10);
  return {};
}

bool LineReader::fill() {
  if (!file_) return false;
  auto n =
      file_->read_some({reinterpret_cast<std::byte*>(buf_.data()), buf_.size()}, path_.c_str());
  if (!n.ok()) error_ = n.error();
  pos_ = 0;
  end_ = n.ok() ? *n : 0;
  return end_ > 0;
}

bool LineReader::next(std::string& line) {
  line.clear();
  too_long_ = false;
  bool any = false;  // a last line without a newline still counts
  for (;;) {
    if (pos_ == end_ && !fill()) break;
    any = true;
    const char* start = buf_.data() + pos_;
    const auto* nl = static_cast<const char*>(std::memchr(start, '\n', end_ - pos_));
    const size_t len = nl != nullptr ? static_cast<size_t>(nl - start) : end_ - pos_;
    // Keep at most kMaxLineBytes + 1 bytes: enough to tell an over-long line, never all of it.
    if (!too_long_) {
      const size_t room = kMaxLineBytes + 1 - line.size();
      line.append(start, std::min(len, room));
      too_long_ = line.size() > kMaxLineBytes;
    }
    pos_ += len + (nl != nullptr ? 1 : 0);
    if (nl != nullptr) break;
  }
  if (!any) return false;
  ++line_number_;
  if (!too_long_ && !line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

}  // namespace tlvlink::tools
