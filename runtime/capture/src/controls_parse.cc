// Parsing control lists from configuration and naming controls the way v4l2-ctl does.
#include <linux/videodev2.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <string>

#include "tlvlink/capture/controls.h"

namespace tlvlink::capture {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// Parses a whole decimal or 0x-hex integer; false on anything else.
bool parse_int(std::string_view text, int64_t& out) {
  const std::string s(text);
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 0);
  if (errno != 0 || end != s.c_str() + s.size()) return false;
  out = v;
  return true;
}

bool valid_key(std::string_view name) {
  for (char c : name) {
    if (!(std::islower(static_cast<unsigned char>(c)) ||
          std::isdigit(static_cast<unsigned char>(c)) || c == '_')) {
      return false;
    }
  }
  return !name.empty();
}

struct WellKnown {
  const char* name;
  uint32_t id;
};
constexpr WellKnown kWellKnown[] = {
    {"auto_exposure", V4L2_CID_EXPOSURE_AUTO},
    {"exposure_auto", V4L2_CID_EXPOSURE_AUTO},
    {"exposure_time_absolute", V4L2_CID_EXPOSURE_ABSOLUTE},
    {"exposure_absolute", V4L2_CID_EXPOSURE_ABSOLUTE},
    {"exposure", V4L2_CID_EXPOSURE_ABSOLUTE},
    {"exposure_dynamic_framerate", V4L2_CID_EXPOSURE_AUTO_PRIORITY},
    {"white_balance_automatic", V4L2_CID_AUTO_WHITE_BALANCE},
    {"white_balance_temperature_auto", V4L2_CID_AUTO_WHITE_BALANCE},
    {"white_balance_temperature", V4L2_CID_WHITE_BALANCE_TEMPERATURE},
    {"white_balance", V4L2_CID_WHITE_BALANCE_TEMPERATURE},
    {"gain", V4L2_CID_GAIN},
    {"zoom_absolute", V4L2_CID_ZOOM_ABSOLUTE},
    {"led", V4L2_CID_ZOOM_ABSOLUTE},
    {"brightness", V4L2_CID_BRIGHTNESS},
    {"contrast", V4L2_CID_CONTRAST},
    {"saturation", V4L2_CID_SATURATION},
    {"hue", V4L2_CID_HUE},
    {"sharpness", V4L2_CID_SHARPNESS},
    {"gamma", V4L2_CID_GAMMA},
    {"backlight_compensation", V4L2_CID_BACKLIGHT_COMPENSATION},
    {"power_line_frequency", V4L2_CID_POWER_LINE_FREQUENCY},
    {"focus_absolute", V4L2_CID_FOCUS_ABSOLUTE},
    {"focus_automatic_continuous", V4L2_CID_FOCUS_AUTO},
};

}  // namespace

uint32_t well_known_control(std::string_view name) {
  for (const WellKnown& w : kWellKnown) {
    if (name == w.name) return w.id;
  }
  return 0;
}

void control_key(const char* driver_name, char* out, size_t out_size) {
  if (out_size == 0) return;
  size_t n = 0;
  bool gap = false;
  for (const char* p = driver_name; *p != '\0' && n + 1 < out_size; ++p) {
    const unsigned char c = static_cast<unsigned char>(*p);
    if (std::isalnum(c)) {
      if (gap && n > 0 && n + 2 < out_size) out[n++] = '_';
      out[n++] = static_cast<char>(std::tolower(c));
      gap = false;
    } else {
      gap = true;
    }
  }
  out[n] = '\0';
}

Result<std::vector<ControlSetting>> parse_controls(std::string_view text) {
  std::vector<ControlSetting> out;
  while (!text.empty()) {
    const size_t cut = text.find_first_of(",;");
    const std::string_view item = trim(text.substr(0, cut));
    text = cut == std::string_view::npos ? std::string_view() : text.substr(cut + 1);
    if (item.empty()) continue;
    const std::string shown(item);
    const size_t eq = item.find('=');
    if (eq == std::string_view::npos) {
      return Error::make(ErrorCode::kInvalidArgument,
                         "control '%s': expected name=value (e.g. gain=0)", shown.c_str());
    }
    const std::string_view key = trim(item.substr(0, eq));
    ControlSetting setting;
    setting.name = std::string(key);
    if (!parse_int(trim(item.substr(eq + 1)), setting.value)) {
      return Error::make(ErrorCode::kInvalidArgument, "control '%s': value is not an integer",
                         shown.c_str());
    }
    int64_t id = 0;
    if (!key.empty() && std::isdigit(static_cast<unsigned char>(key.front()))) {
      if (!parse_int(key, id) || id <= 0 || id > 0xFFFFFFFF) {
        return Error::make(ErrorCode::kInvalidArgument, "control '%s': '%s' is not a control id",
                           shown.c_str(), setting.name.c_str());
      }
      setting.id = static_cast<uint32_t>(id);
    } else if (!valid_key(key)) {
      return Error::make(ErrorCode::kInvalidArgument,
                         "control '%s': names are lower-case letters, digits and '_' "
                         "(v4l2-ctl's keys, e.g. exposure_time_absolute)",
                         shown.c_str());
    }
    if (out.size() == kMaxControls) {
      return Error::make(ErrorCode::kInvalidArgument, "more than %zu controls", kMaxControls);
    }
    out.push_back(std::move(setting));
  }
  return out;
}

}  // namespace tlvlink::capture
