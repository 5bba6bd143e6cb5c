#pragma once
// Test support for the vivid driver (the kernel's virtual video test driver), as loaded by the
// board rig (tools/rig: `rig_vivid_load` = "modprobe vivid n_devs=1 node_types=0x101"): finding
// its capture and output nodes, its controls by v4l2-ctl key, and a V4l2Config for its nodes.

#include <cstdint>
#include <optional>
#include <string>

#include "tlvlink/capture/v4l2_source.h"

namespace tlvlink::capture::vivid {

struct Nodes {
  std::string capture;  // /dev/videoN of "vivid-000-vid-cap"
  std::string output;   // /dev/videoM of "vivid-000-vid-out" ("" when not loaded with one)
};

// The nodes of vivid instance 0, or nullopt when vivid is not loaded.
std::optional<Nodes> find_nodes();

// Skip reason when vivid is absent (the host), or "" when it is present.
std::string absent_reason();

// ioctl() retried on EINTR; 0 or the errno. (The runtime's own is internal to runtime/capture.)
int xioctl(int fd, unsigned long req, void* arg);

// Destructive tests (unbind, module reload) run only inside the rig (TLVLINK_RIG=1).
bool in_rig();

// Control by v4l2-ctl key on a node, through its own fd; 0 or an errno (ENOENT: no such key).
int set_control(const std::string& dev, const char* key, int64_t value);
int get_control(const std::string& dev, const char* key, int64_t& value);

// Input 0 (webcam) or 3 (HDMI) on the capture node; output 1 (HDMI) on the output node.
int select_input(const std::string& dev, int input);

// A config for vivid's capture node: by path (vivid has no USB identity), OSD text off so frames
// hold only the test pattern, short watchdog and backoff so faults resolve fast under TCG.
V4l2Config capture_config(const Nodes& nodes, image::PixelFormat format, int32_t width,
                          int32_t height, double fps);

// Monotonic now, for frame ages.
int64_t now_ns();
// This process's CPU time in seconds (CLOCK_PROCESS_CPUTIME_ID): a spinning loop shows here.
double cpu_seconds();
// Writes `text` to a sysfs file (unbind / bind a driver); false when the kernel refused it.
bool write_sysfs(const char* path, const char* text);

}  // namespace tlvlink::capture::vivid
