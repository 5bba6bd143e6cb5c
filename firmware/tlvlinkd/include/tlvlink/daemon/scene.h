#pragma once
// A scene (boards/scenes/*.toml): what one deployment needs — its sensors, the heads it reports,
// grasp prediction on or off, its output link and contact gating. `tlvlink strip` keeps only the
// scene's heads in a model, `tlvlink flash` builds a board image without the components the
// scene does not use and installs the daemon configuration made from it (scene_config_toml).
// Errors name the file, line and key ("FILE:LINE: KEY: what is wrong"), like load_config.

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::daemon {

struct SceneSensor {
  std::string name;             // "left"
  std::string sensor_model;     // gelsight-mini, digit, ... (capture/sensor_models.h)
  std::string finger = "none";  // A, B or none
  std::string source = "v4l2";  // v4l2 or libcamera (a scene describes live cameras)
  std::string device;           // usb:VID:PID[:SERIAL] (v4l2) or the libcamera camera id
};

struct Scene {
  std::string path, name;  // name: the file name without .toml
  std::string description;
  std::vector<std::string>
      heads;                  // per-frame heads kept and reported ("material", "zero-shot:grasp")
  std::string grasp = "off";  // detected, commanded or off: off drops the grasp head
  std::vector<std::string> outputs = {"jsonl:-"};  // tlvlinkd `output` values
  bool contact_gating = true;
  int32_t golden_pairs = 2;  // golden pairs kept in the model (>= 1: verified at install)
  std::vector<SceneSensor> sensors;
};

// What a scene's deployment uses: the build leaves out the rest.
struct SceneNeeds {
  bool stream = false;     // a stream link (serial, pty or usb): the protocol and transports
  bool usb = false;        // the USB (FunctionFS) transport
  bool libcamera = false;  // a libcamera source
  bool zero_shot = false;  // a zero-shot head among `heads`
};
SceneNeeds scene_needs(const Scene& scene);

Result<Scene> load_scene(const std::string& path);
Result<Scene> parse_scene(std::string_view toml, const std::string& path);
// boards/scenes/NAME.toml under `scenes_dir`; an unknown name is an error listing the scenes.
Result<Scene> find_scene(const std::string& scenes_dir, const std::string& name);

// The tlvlinkd configuration (TOML text) for `scene` running `model_path` with `threads`
// encoder threads; load_config accepts it (a test checks every shipped scene).
std::string scene_config_toml(const Scene& scene, const std::string& model_path, int32_t threads,
                              const std::string& origin);

}  // namespace tlvlink::daemon
