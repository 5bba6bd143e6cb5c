// Camera recordings named in a labels file as labelled frames (labelled_frames.h).

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "tlvlink/capture/recording.h"
#include "tlvlink/eval/labelled_frames.h"
#include "tlvlink/io/line_reader.h"

namespace tlvlink::eval {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, '\t')) out.push_back(field);
  return out;
}

// "-" or empty: no bound (nullopt); else seconds >= 0.
bool parse_seconds(const std::string& text, std::optional<double>& out) {
  if (text.empty() || text == "-") return true;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !std::isfinite(v) || v < 0) return false;
  out = v;
  return true;
}

struct Line {
  std::string recording, cls, group;
  std::optional<double> from, to;
  int64_t number = 0;
};

}  // namespace

Result<LabelledFrames> read_labelled_recordings(const std::string& labels_file, int32_t stride) {
  TLV_ENSURE(stride >= 1, ErrorCode::kInvalidArgument, "recordings: stride %d (>= 1)", stride);
  tools::LineReader reader;
  TLV_TRY(reader.open(labels_file));
  const fs::path base = fs::path(labels_file).parent_path();
  std::vector<Line> lines;
  std::string text;
  while (reader.next(text)) {
    if (text.empty() || text[0] == '#') continue;
    const std::vector<std::string> f = split_tabs(text);
    Line l;
    l.number = reader.line_number();
    const bool shape =
        (f.size() == 2 || f.size() == 4 || f.size() == 5) && !f[0].empty() && !f[1].empty();
    const bool times =
        shape && (f.size() < 4 || (parse_seconds(f[2], l.from) && parse_seconds(f[3], l.to)));
    TLV_ENSURE(
        shape && times && (!l.from || !l.to || *l.from < *l.to), ErrorCode::kFormat,
        "%s:%lld: expected \"<recording><TAB><class>[<TAB><from_s><TAB><to_s>][<TAB><group>]\" "
        "with from < to (seconds, or -), got \"%.100s\"",
        labels_file.c_str(), static_cast<long long>(l.number), text.c_str());
    l.recording = fs::path(f[0]).is_absolute() ? f[0] : (base / f[0]).string();
    l.cls = f[1];
    l.group = f.size() == 5 && !f[4].empty() ? f[4] : f[0];
    lines.push_back(std::move(l));
  }
  TLV_TRY(reader.error());

  LabelledFrames set;
  set.dir = labels_file;
  set.grouping = Grouping::kRecordings;
  for (const Line& l : lines) set.classes.push_back(l.cls);
  std::sort(set.classes.begin(), set.classes.end());
  set.classes.erase(std::unique(set.classes.begin(), set.classes.end()), set.classes.end());
  TLV_ENSURE(set.classes.size() >= 2, ErrorCode::kFormat,
             "%s: %zu class(es); a head needs at least two", labels_file.c_str(),
             set.classes.size());
  for (const Line& l : lines) {
    auto opened = capture::RecordingReader::open(l.recording);
    if (!opened.ok()) {
      return opened.error().with_context("%s:%lld", labels_file.c_str(),
                                         static_cast<long long>(l.number));
    }
    const capture::RecordingReader& rec = *opened;
    const auto label = static_cast<int32_t>(
        std::find(set.classes.begin(), set.classes.end(), l.cls) - set.classes.begin());
    const int64_t start_ns = rec.summary().first_offset_ns;
    int64_t taken = 0, index = 0;
    capture::RecordInfo info;
    for (uint64_t at = rec.first_record();;) {
      auto more = rec.record_at(at, info);
      if (!more.ok())
        return more.error().with_context("%s:%lld", labels_file.c_str(),
                                         static_cast<long long>(l.number));
      if (!*more) break;
      at = info.next;
      if ((info.flags & (capture::kRecordRepeat | capture::kRecordErrorFlag)) != 0) continue;
      const double t = static_cast<double>(info.offset_ns - start_ns) * 1e-9;
      if ((l.from && t < *l.from) || (l.to && t >= *l.to)) continue;
      if (index++ % stride != 0) continue;
      char relative[64];
      std::snprintf(relative, sizeof relative, "@%.3fs", t);
      set.frames.push_back({l.recording, fs::path(l.recording).filename().string() + relative,
                            label, l.group, info.offset});
      ++taken;
    }
    TLV_ENSURE(taken > 0, ErrorCode::kFormat, "%s:%lld: no frame of %s in the range given",
               labels_file.c_str(), static_cast<long long>(l.number), l.recording.c_str());
  }
  return set;
}

}  // namespace tlvlink::eval
