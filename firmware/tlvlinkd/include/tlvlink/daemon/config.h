#pragma once
// tlvlinkd's configuration (TOML): the model, the sensors and their sources, contact gating,
// grasps, smoothing, output and threads. Loading validates everything before the daemon touches
// a device: an unknown key, a wrong type or a value out of range is an error naming the file,
// line and key. Annotated example: firmware/tlvlinkd/tlvlinkd.toml.

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/capture/controls.h"
#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/error.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/pipeline/frame_processor.h"

namespace tlvlink::daemon {

// replay: a recorded raw stream (capture/recording.h), e.g. a simulated finger written by
// `tlvlink sim scenario`, played at the camera's pace.
enum class SourceKind : uint8_t { kV4l2, kLibcamera, kReplay };
const char* source_kind_name(SourceKind kind);  // "v4l2", "libcamera", "replay"

struct SensorConfig {
  std::string name;          // "left": names the sensor in outputs and errors
  std::string sensor_model;  // "gelsight-mini", "digit", ... (capture/sensor_models.h)
  int32_t finger = -1;       // 0 = A, 1 = B, -1 = not part of a grasp
  SourceKind source = SourceKind::kV4l2;
  std::string device;  // v4l2: "usb:VID:PID[:SERIAL]" or a path; libcamera: camera
                       // id; replay: the recording
  // The camera format (defaults from the sensor model) and the view of the processed frame.
  image::FrameFormat format;
  double fps = 0;
  image::SensorView view;
  uint32_t buffers = 4, warmup_frames = 0;
  int32_t watchdog_ms = 1000;
  bool accept_other_size = false;
  bool wait_for_device = true;  // a camera absent at start is an outage, not an exit
  std::vector<capture::ControlSetting> controls;
  bool realtime = true, loop = false, verify = true;  // replay (verify: frame CRC-32s)
};

enum class ControlInput : uint8_t { kNone, kStdin };
// FrameImages on the stream link (protocol 1.2): none, the decoded camera view, the model's input.
enum class FrameImageKind : uint8_t { kOff, kView, kInput };

struct DaemonConfig {
  std::string path;  // the file it came from
  std::string model;
  std::string executor = "xnnpack";
  int32_t threads = 1;
  bool verify_model = true;  // run the model's golden pairs before streaming
  // A public key file (tlvlink keygen's BASE.pub): when set, the model must be signed by it
  // (runtime/model model_integrity.h); empty: signatures are not required.
  std::string model_public_key;
  // Where records go, one or more of: jsonl:- (stdout), jsonl:FILE, and one stream link
  // serial:PATH[,baud=N][,flow=rtscts], pty:LINK or usb[...] (runtime/transport).
  std::vector<std::string> outputs = {"jsonl:-"};
  ControlInput control = ControlInput::kNone;
  // A recorded controller's closed / lifting marks for a replayed session, tied to the frames
  // they were given at ("FINGER SEQUENCE COMMAND" lines: `tlvlink sim scenario` writes
  // DIR/commands.txt); empty: none. Given beside `control` or instead of it.
  std::string command_script;
  int32_t status_interval_ms = 1000;
  bool status_line = false;    // a live status line on stderr
  int32_t queue_frames = 2;    // decoded frames waiting per sensor (older ones dropped)
  int32_t output_queue = 256;  // records waiting for the output (older ones dropped)
  int64_t run_for_ms = 0;      // 0: until SIGTERM/SIGINT; > 0: stop after this long
  int64_t max_frames = 0;      // 0: no limit; > 0: stop after this many frames in all
  // A JPEG of each sensor's view or model input now and then on the stream link (needs one);
  // checked to fit a FrameImage at start and by --check alike.
  FrameImageKind frame_images = FrameImageKind::kOff;
  int32_t frame_images_per_second = 2;  // per sensor, [1, 15]
  int32_t frame_image_quality = 70;     // JPEG quality, [20, 95]
  int32_t frame_image_max_side = 320;   // the view is scaled down to fit, [16, 1024]
  pipeline::ProcessorOptions processing;
  std::vector<SensorConfig> sensors;
};

// Limits (exceeding one is an error naming the key).
inline constexpr int32_t kMaxQueueFrames = 16, kMaxOutputQueue = 4096, kMaxThreads = 64;

// load_config = parse_config + check_config_paths: what `--check`, start and SIGHUP all run.
Result<DaemonConfig> load_config(const std::string& path);
Result<DaemonConfig> parse_config(std::string_view toml, const std::string& name);

// The files the configuration names, each opened non-blocking and checked to be what start will
// open (kInvalidArgument naming the key and path): model_public_key, command_script and each
// replay recording a regular file; a jsonl:FILE output absent, a regular file or a character
// device (never a FIFO). The model itself is checked by --verify and at start.
Status check_config_paths(const DaemonConfig& config);
// One `jsonl:` target (without the prefix) as check_config_paths checks it.
Status check_jsonl_target(const std::string& path);

}  // namespace tlvlink::daemon
