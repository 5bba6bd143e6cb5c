#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "sources.h is internal to firmware/tlvlinkd"
#endif
// The configured sensors' frame sources, created and started (an absent camera with
// wait_for_device is an outage from the start, not an error).

#include <memory>
#include <vector>

#include "tlvlink/capture/frame_source.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/error.h"

namespace tlvlink::daemon::internal {

Result<std::vector<std::unique_ptr<capture::FrameSource>>> make_sources(const DaemonConfig& config);

}  // namespace tlvlink::daemon::internal
