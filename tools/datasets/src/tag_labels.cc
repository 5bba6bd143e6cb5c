// Touch-and-Go label lines: "SESSION/NNNNNNNNNN.jpg,<id>".

#include <charconv>

#include "line_io.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "touch_common.h"

namespace tlvlink::datasets {

Result<TagLabelLine> parse_tag_label_line(std::string_view line) {
  const size_t comma = line.rfind(',');
  TLV_ENSURE(comma != std::string_view::npos, ErrorCode::kFormat,
             "expected \"SESSION/NNNNNNNNNN.jpg,<id>\" (no comma)");
  TagLabelLine out;
  out.key = std::string(trim(line.substr(0, comma)));
  TLV_ENSURE(
      is_safe_relative_path(out.key) && parse_tag_frame_key(out.key, out.session, out.frame_index),
      ErrorCode::kFormat, "'%.80s' is not SESSION/NNNNNNNNNN.jpg", out.key.c_str());
  const std::string_view id = trim(line.substr(comma + 1));
  int32_t label = 0;
  const auto [end, ec] = std::from_chars(id.data(), id.data() + id.size(), label);
  TLV_ENSURE(ec == std::errc() && end == id.data() + id.size() && !id.empty(), ErrorCode::kFormat,
             "label '%.40s' is not an integer", std::string(id).c_str());
  out.label = label;
  return out;
}

}  // namespace tlvlink::datasets
