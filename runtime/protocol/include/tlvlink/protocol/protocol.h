#pragma once
// Umbrella header of the stream protocol (tlvlink_protocol): frames, messages, encoding,
// decoding, clock offset estimation. runtime/protocol/README.md is the specification.

#include "tlvlink/protocol/clock.h"
#include "tlvlink/protocol/cobs.h"
#include "tlvlink/protocol/crc32.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/frame.h"
#include "tlvlink/protocol/messages.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/protocol/views.h"
#include "tlvlink/protocol/wire.h"
