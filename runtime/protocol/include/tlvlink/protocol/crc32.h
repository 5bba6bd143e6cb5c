#pragma once
// The stream's CRC-32 is the project's one (runtime/core: zlib's, 0xCBF43926 for "123456789").

#include "tlvlink/crc32.h"

namespace tlvlink::protocol {

using tlvlink::crc32;

}  // namespace tlvlink::protocol
