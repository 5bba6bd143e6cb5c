#pragma once
// The Hello a board sends first on every (re)connect, built once at start from the model, the
// sensors and the output names. The Hello's strings and lists are views into this object: keep
// it alive (and unmoved: it is neither copyable nor movable) while the Hello is in use.

#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/model.h"
#include "tlvlink/protocol/messages.h"
#include "tlvlink/stream/names.h"

namespace tlvlink::stream {

// Who is speaking: the board program says (host name, board, firmware version, boot id).
struct BoardIdentity {
  std::string device;  // the host name
  std::string board;   // the board build's name (TLVLINK_BOARD)
  std::string firmware_version;
  uint64_t boot_id = 0;  // changes at every start of the program (e.g. its pid)
};

struct SensorDescription {
  std::string name, model;   // "left", "gelsight-mini"
  std::string pixel_format;  // image::pixel_format_name of the camera's format
  int32_t width = 0, height = 0;
  double fps = 0;
};

class HelloBuilder {
 public:
  // `model_id_fallback` names the model when its metadata has no name (e.g. its file path).
  HelloBuilder(const BoardIdentity& board, const Model& model, std::string_view model_id_fallback,
               std::span<const SensorDescription> sensors, const OutputNames& names);
  HelloBuilder(const HelloBuilder&) = delete;
  HelloBuilder& operator=(const HelloBuilder&) = delete;

  const protocol::Hello& hello() const { return hello_; }

 private:
  std::deque<std::string> strings_;  // a deque: appending never moves the strings views see
  std::vector<std::vector<std::string_view>> label_views_;
  std::vector<protocol::SensorInfo> sensors_;
  std::vector<protocol::HeadInfo> heads_;
  std::vector<std::string_view> stage_names_;
  protocol::Hello hello_;
};

}  // namespace tlvlink::stream
