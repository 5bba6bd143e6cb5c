#pragma once
// A recording with every message type and every case a reader must handle (chunks that cut
// frames, the client's own commands and their consumed replies, a clock offset of +5 s, an
// unknown message type, fields from a newer minor version, garbage, a corrupted frame, a frame
// of major version 2, a sequence gap, a delayed message, a reconnect and a board restart).
// Deterministic: the C++ and Python replay tests compare their outputs on it.

#include <string>

#include "tlvlink/error.h"

namespace tlvlink::listen {

Status write_fixture_recording(const std::string& path, bool cut_last_record);

// A link up, a Hello, an ErrorReport whose text is not UTF-8 (bytes 0xFF 0xFE inside "bad ...")
// and an ErrorReport "after" it: a reader must print both (issue 31).
Status write_non_utf8_recording(const std::string& path);

}  // namespace tlvlink::listen
