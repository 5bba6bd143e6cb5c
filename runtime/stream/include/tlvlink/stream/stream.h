#pragma once
// runtime/stream: what a board program needs to speak the prediction stream (runtime/protocol)
// from the pipeline's records (runtime/pipeline): the Hello, the messages, the commands.

#include "tlvlink/stream/commands.h"
#include "tlvlink/stream/hello.h"
#include "tlvlink/stream/json_lines.h"
#include "tlvlink/stream/line_buffer.h"
#include "tlvlink/stream/message_mapper.h"
#include "tlvlink/stream/names.h"
#include "tlvlink/stream/stages.h"
