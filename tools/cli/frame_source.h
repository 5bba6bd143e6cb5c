#pragma once
// The deployment preprocessing as the encoder generator's FramePreprocessor, and synthetic
// frames as model inputs (bench, tests).

#include <vector>

#include "tlvlink/model.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::cli {

quantize::FramePreprocessor tool_preprocessor();

// A synthetic touch frame, preprocessed for `model` (graph input 0 as float).
Result<std::vector<float>> synthetic_input(const Model& model, uint64_t seed);

}  // namespace tlvlink::cli
