#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "board_hello.h is internal to firmware/tlvlinkd"
#endif
// What the daemon's outputs say about it: the Hello (who is speaking, the model, the sensors)
// every output starts with, and the run's totals as the stream's Stats counts them. One place for
// both outputs (the stream link and the JSON lines), so they cannot say different things.

#include <memory>

#include "run_totals.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/model.h"
#include "tlvlink/stream/hello.h"
#include "tlvlink/stream/message_mapper.h"

namespace tlvlink::daemon::internal {

// This daemon's Hello (host name, board, version, pid as boot id, the configured sensors).
std::unique_ptr<stream::HelloBuilder> make_hello(const DaemonConfig& config, const Model& model,
                                                 const stream::OutputNames& names);

// The run's totals by the stream's drop causes (stream::MessageMapper::stats).
stream::StreamTotals stream_totals(const RunTotals& totals);

}  // namespace tlvlink::daemon::internal
