#pragma once
#ifndef TLVLINK_IO_PRIVATE
#error "npy_header.h is internal to tools/io: include its public headers instead"
#endif
// The .npy header: a Python dict literal such as
//   {'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }
// parsed by a small strict tokenizer (no eval): exactly the three keys, each once.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"

namespace tlvlink::tools {

struct NpyHeader {
  std::string descr;
  bool fortran_order = false;
  std::vector<int64_t> shape;
};

// Parses the dict text (trailing spaces / newline allowed). Errors are prefixed with `name`.
Result<NpyHeader> parse_npy_header_dict(std::string_view text, const std::string& name);
// The dict numpy would write for this dtype and shape (without padding).
std::string format_npy_header_dict(DType dtype, const std::vector<int64_t>& shape);

}  // namespace tlvlink::tools
