#include "tlvlink/boards/build_options.h"

namespace tlvlink::boards {

Result<BuildPlan> plan_build(const Board& board, const daemon::Scene& scene) {
  const daemon::SceneNeeds needs = daemon::scene_needs(scene);
  BuildPlan p;
  const auto off = [&](const char* name, const char* what, const std::string& why) {
    p.options.push_back({name, "OFF", why});
    p.left_out.push_back(std::string(what) + " (" + why + ")");
  };
  for (const char* o :
       {"TLVLINK_BUILD_TESTS", "TLVLINK_BUILD_HOST_TOOLS", "TLVLINK_BUILD_BENCHMARKS",
        "TLVLINK_BUILD_TRAINER", "TLVLINK_BUILD_FUZZERS"}) {
    p.options.push_back({o, "OFF", "not part of a board image"});
  }
  p.left_out.push_back("tests, host tools (tlvlink CLI, quantizer), trainer, benchmarks, fuzzers");
  TLV_ENSURE(!needs.libcamera || board.option("TLVLINK_WITH_LIBCAMERA") == "ON" || !board.cross,
             ErrorCode::kInvalidArgument,
             "scene '%s' uses a libcamera source, but board '%s' is built without libcamera "
             "(TLVLINK_WITH_LIBCAMERA=%s: no arm64 libcamera in the cross sysroot)",
             scene.name.c_str(), board.name.c_str(),
             board.option("TLVLINK_WITH_LIBCAMERA").c_str());
  p.options.push_back({"TLVLINK_WITH_LIBCAMERA", needs.libcamera ? "ON" : "OFF",
                       needs.libcamera ? "a libcamera source" : "every sensor is a V4L2 camera"});
  if (!needs.libcamera) p.left_out.push_back("libcamera source (every sensor is a V4L2 camera)");
  if (!needs.stream) {
    off("TLVLINK_WITH_USB", "USB transport", "no stream link: JSON lines only");
    off("TLVLINK_WITH_SERIAL", "serial transports and the sender",
        "no stream link: JSON lines only");
    // The daemon names its outputs and stages through runtime/stream, which links the protocol
    // library (flatbuffers only, no transport): kept, with no link to send over.
    p.options.push_back(
        {"TLVLINK_WITH_PROTOCOL", "ON", "the daemon's output names (runtime/stream)"});
  } else {
    p.options.push_back({"TLVLINK_WITH_PROTOCOL", "ON", "a stream link"});
    p.options.push_back({"TLVLINK_WITH_SERIAL", "ON", "a stream link"});
    if (needs.usb) {
      p.options.push_back({"TLVLINK_WITH_USB", "ON", "output usb"});
    } else {
      off("TLVLINK_WITH_USB", "USB transport", "the stream link is serial");
    }
  }
  // Not gated by an option (small, or shared with every scene): say so instead of pretending.
  p.built_in.push_back("JSON lines output (always built: the daemon's events and stats)");
  p.built_in.push_back(needs.zero_shot ? "zero-shot heads (used)"
                                       : "zero-shot head code (no build option; the scene's model "
                                         "carries no zero-shot head)");
  return p;
}

}  // namespace tlvlink::boards
