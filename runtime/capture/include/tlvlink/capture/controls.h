#pragma once
// Camera controls from configuration, applied when a source opens its device and again after
// every reconnect (a replugged camera comes back with its defaults).
//
//   auto controls = parse_controls("auto_exposure=1, exposure_time_absolute=180, "
//                                  "white_balance_automatic=0, white_balance_temperature=4500,
//                                  gain=0");
//
// A name is resolved in this order: a number (decimal or 0x...) is the V4L2 control id; a
// well-known name (table below, both the current and the pre-5.x kernel spellings) is its
// standard V4L2 id; anything else is matched against the keys of the controls the device offers
// (v4l2-ctl's keys: the driver's name lower-cased, other characters -> '_', e.g.
// "percentage_of_dropped_buffers"). A control the device does not offer, a value outside its
// range, or a refused write is an error naming the control when the source opens. Settings are
// applied in the order given: switch an automatic mode off before the manual value it governs.
//
// Well-known names (the controls tactile sensors need): auto_exposure (exposure_auto; 1 = manual),
// exposure_time_absolute (exposure_absolute, exposure), white_balance_automatic
// (white_balance_temperature_auto), white_balance_temperature (white_balance), gain,
// zoom_absolute (led: DIGIT drives its LEDs through the UVC zoom control), brightness, contrast,
// saturation, hue, sharpness, gamma, backlight_compensation, power_line_frequency,
// exposure_dynamic_framerate, focus_absolute, focus_automatic_continuous.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::capture {

struct ControlSetting {
  std::string name;  // as written in the configuration ("gain", "0x009a0902")
  uint32_t id = 0;   // V4L2 control id when written as a number; 0: look the name up on the device
  int64_t value = 0;
};

// "name=value" items separated by ',' or ';' (whitespace ignored). Errors name the item.
// At most kMaxControls items.
inline constexpr size_t kMaxControls = 32;
Result<std::vector<ControlSetting>> parse_controls(std::string_view text);

// The v4l2-ctl key of a driver's control name: "White Balance Temperature" ->
// "white_balance_temperature". Writes at most out_size - 1 characters plus a terminator.
void control_key(const char* driver_name, char* out, size_t out_size);

// The standard V4L2 id of a well-known name (list above); 0 when the name is not one of them.
uint32_t well_known_control(std::string_view name);

}  // namespace tlvlink::capture
