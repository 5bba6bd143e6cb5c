// truth.jsonl: the scenario's ground truth.

#include "truth.h"

#include <cctype>

namespace tlvlink::score::internal {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Result<Truth> read_truth(const std::string& path) {
  Truth t;
  bool header = false;
  TLV_TRY(read_lines(path, [&](const json& j) -> Status {
    const std::string type = j.value("type", "");
    if (type == "scenario") {
      header = true;
      t.frames = j.value("frames", int64_t{0});
      TLV_ENSURE(t.frames > 0 && t.frames <= 100'000'000, ErrorCode::kFormat,
                 "scenario line: frames = %lld", static_cast<long long>(t.frames));
      for (auto& f : t.fingers) f.resize(static_cast<size_t>(t.frames));
    } else if (type == "event") {
      TruthEvent e;
      e.kind = j.value("kind", "");
      if (j.contains("success") && j["success"].is_boolean()) {
        e.has_success = true;
        e.success = j["success"].get<bool>();
      }
      for (const char* head : {"material", "hard_soft", "rough_smooth"}) {
        e.labels[head] =
            j.contains(head) && j[head].is_string() ? lower(j[head].get<std::string>()) : "";
        // A press head (tools/eval press_head.h) named after the label it learns.
        e.labels[std::string(head) + "_press"] = e.labels[head];
      }
      const auto id = j.value("id", int64_t{-1});
      TLV_ENSURE(id == static_cast<int64_t>(t.events.size()), ErrorCode::kFormat,
                 "event id %lld out of order", static_cast<long long>(id));
      t.events.push_back(std::move(e));
    } else if (type == "frame") {
      TLV_ENSURE(header, ErrorCode::kFormat, "frame line before the scenario line");
      const std::string finger = j.value("finger", "");
      const auto seq = j.value("seq", int64_t{-1});
      TLV_ENSURE((finger == "A" || finger == "B") && seq >= 0 && seq < t.frames, ErrorCode::kFormat,
                 "frame line with finger '%s' seq %lld", finger.c_str(),
                 static_cast<long long>(seq));
      TruthFrame& f = t.fingers[finger == "A" ? 0 : 1][static_cast<size_t>(seq)];
      f.contact = j.value("contact", false);
      f.force_n = j.value("force_n", 0.0);
      f.signal_dn = j.value("signal_dn", 1e9);
      f.event = j.value("event", -1);
    }
    return {};
  }));
  TLV_ENSURE(header, ErrorCode::kFormat, "%s: no scenario line (not a truth.jsonl?)", path.c_str());
  return t;
}

int32_t grasp_event(int64_t seq, const Truth& truth) {
  if (seq < 0 || truth.frames <= 0) return -1;
  const int32_t event = truth.fingers[0][static_cast<size_t>(seq % truth.frames)].event;
  if (event < 0 || !truth.events[static_cast<size_t>(event)].has_success) return -1;
  return event;
}

}  // namespace tlvlink::score::internal
