#include "touch_common.h"

#include <cstdio>

#include "images.h"
#include "line_io.h"

namespace tlvlink::datasets {

std::string tag_frame_key(const std::string& session, int32_t frame_index) {
  char name[32];
  std::snprintf(name, sizeof name, "%010d.jpg", frame_index);
  return session + "/" + name;
}

bool parse_tag_frame_key(std::string_view key, std::string& session, int32_t& frame_index) {
  const size_t slash = key.find('/');
  if (slash == std::string_view::npos || slash == 0 || key.find('/', slash + 1) != key.npos)
    return false;
  const std::string_view file = key.substr(slash + 1);
  const size_t dot = file.rfind('.');
  if (dot == std::string_view::npos || dot == 0 || dot > 10) return false;
  const std::string_view ext = file.substr(dot);
  if (ext != ".jpg" && ext != ".jpeg" && ext != ".png") return false;
  int64_t n = 0;
  for (char c : file.substr(0, dot)) {
    if (c < '0' || c > '9') return false;
    n = n * 10 + (c - '0');
  }
  if (n > INT32_MAX) return false;
  session.assign(key.substr(0, slash));
  frame_index = static_cast<int32_t>(n);
  return true;
}

Status check_touch_sample(const TouchSample& s) {
  TLV_ENSURE(is_safe_name(s.session), ErrorCode::kInvalidArgument,
             "touch sample session '%s' is not a safe folder name (letters, digits, _-.)",
             s.session.c_str());
  TLV_ENSURE(s.frame_index >= 0, ErrorCode::kInvalidArgument, "touch sample %s: frame_index %d < 0",
             s.session.c_str(), s.frame_index);
  const std::string key = tag_frame_key(s.session, s.frame_index);
  TLV_TRY(check_image(s.touch, key + " touch image"));
  TLV_TRY(check_image(s.vision, key + " vision image"));
  return {};
}

Result<bool> TouchSplitter::is_test(const TouchSample& sample) {
  const bool test = objects_.is_test(std::to_string(sample.object_id));
  auto [it, inserted] = sessions_.emplace(sample.session, test);
  if (inserted) {
    if (test) ++test_sessions_;
  } else {
    TLV_ENSURE(it->second == test, ErrorCode::kInvalidArgument,
               "session %s holds objects of both splits (object %d); one object per session",
               sample.session.c_str(), sample.object_id);
  }
  return test;
}

void TouchSplitter::fill(WriteSummary& summary) const {
  summary.objects = static_cast<int64_t>(sessions_.size());
  summary.test_objects = test_sessions_;
}

std::string join_phrases(const std::vector<std::string>& phrases) {
  std::string s;
  for (size_t i = 0; i < phrases.size(); ++i) {
    if (i) s += ", ";
    s += phrases[i];
  }
  return s;
}

std::vector<std::string> split_phrases(std::string_view desc) {
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = desc.find(',', start);
    const std::string_view piece =
        trim(desc.substr(start, comma == desc.npos ? desc.npos : comma - start));
    if (!piece.empty()) out.emplace_back(piece);
    if (comma == desc.npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace tlvlink::datasets
