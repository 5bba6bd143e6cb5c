#pragma once
// The frames of the runtime's stability suite: every scene of the simulator's extreme set
// (tools/sim/include/tlvlink/sim/extreme.h) rendered on its own sensor, plus synthetic uint8
// frames no sensor should produce but a broken camera or driver can: all black, all 255, pixel
// and block checkerboards at full contrast, uniform noise, a single hot pixel, and frames much
// smaller and larger than the models' inputs.

#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/io/image.h"

namespace tlvlink::testing {

struct NamedFrame {
  std::string name;
  tools::Image image;
};

// Deterministic (fixed seeds). Errors: a renderer failure, named by the case.
Result<std::vector<NamedFrame>> stability_frames();

}  // namespace tlvlink::testing
