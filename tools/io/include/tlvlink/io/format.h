#pragma once
// Text forms the host tools print: shapes, byte counts, printf onto a string.

#include <cstddef>
#include <string>

#include "tlvlink/graph.h"

namespace tlvlink::tools {

// "[1, 128, 128, 3]"
std::string shape_string(const Shape& shape);
// "1.50 MB" / "12.3 kB" / "512 B" (decimal units)
std::string human_bytes(size_t bytes);
// printf onto the end of `out` (report and table builders); returns `out`.
[[gnu::format(printf, 2, 3)]] std::string& appendf(std::string& out, const char* format, ...);

}  // namespace tlvlink::tools
