#pragma once
// Umbrella header of runtime/capture (tests include it alone to prove it is self-contained).

#include "tlvlink/capture/controls.h"
#include "tlvlink/capture/device_select.h"
#include "tlvlink/capture/frame_accounting.h"
#include "tlvlink/capture/frame_check.h"
#include "tlvlink/capture/frame_source.h"
#include "tlvlink/capture/outage.h"
#include "tlvlink/capture/reconnect_backoff.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/replay_source.h"
#include "tlvlink/capture/v4l2_source.h"
