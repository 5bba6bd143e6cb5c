#pragma once
// Frames as model inputs through the deployment preprocessing (runtime/image): the reference
// encoder's FramePreprocessor (gen-reference, tests, the fuzz corpus) and a synthetic touch
// frame preprocessed for a model (bench, tests).

#include <cstdint>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::quantize {

// image::preprocess behind the reference encoder's FramePreprocessor interface.
FramePreprocessor deployment_preprocessor();

// A synthetic touch frame (synthetic_touch_frame, a quarter larger than the model input on each
// side), preprocessed for `model` (graph input 0 as float). Error: the model has no input spec.
Result<std::vector<float>> synthetic_input(const Model& model, uint64_t seed);

}  // namespace tlvlink::quantize
