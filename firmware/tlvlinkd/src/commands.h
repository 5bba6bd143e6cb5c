#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "commands.h is internal to firmware/tlvlinkd"
#endif
// Commands from the controller (stdin lines, the stream link, a replayed command script) to the
// inference thread, which owns the pipeline: a small fixed queue, never blocking the sender. The
// commands themselves and their parsing are runtime/stream's (tlvlink/stream/commands.h).

#include <array>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/drop_oldest_ring.h"
#include "tlvlink/error.h"
#include "tlvlink/stream/commands.h"

namespace tlvlink::daemon::internal {

using stream::Command;
using stream::CommandKind;
using stream::parse_command;

// A controller's closed / lifting marks tied to frames (`command_script`): the command is given
// when the inference thread takes `sensor`'s frame `sequence` (or the first one after it), at
// that frame's capture time, so a replayed session gets its marks exactly where the recorded
// controller gave them.
struct ScriptedCommand {
  int32_t sensor = 0;
  uint64_t sequence = 0;
  CommandKind kind = CommandKind::kClosed;
};
// Lines "FINGER SEQUENCE COMMAND" (finger A or B, command closed or lifting; '#' starts a
// comment), ordered by sequence. sensor_of_finger[0|1]: the sensor index of finger A / B, -1
// when no sensor is that finger. Errors name path:line and what is wrong.
Result<std::vector<ScriptedCommand>> load_command_script(const std::string& path,
                                                         const int32_t sensor_of_finger[2]);

class CommandQueue {
 public:
  static constexpr size_t kCapacity = 32;
  bool push(const Command& c);  // false when full (the newest command is dropped and counted)
  bool pop(Command& out);
  uint64_t dropped() const;

 private:
  mutable std::mutex mutex_;
  std::array<Command, kCapacity> storage_{};
  DropOldestRing<Command> ring_{storage_};
};

}  // namespace tlvlink::daemon::internal
