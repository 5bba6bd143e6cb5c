#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "augment.h is internal to tools/trainer: include its public headers instead"
#endif
// Photometric augmentation of cached touch frames (trainer.h AugmentOptions). No libtorch:
// operates on the uint8 HWC cache, so the result is a camera-like frame the runtime could see.

#include <cstdint>

#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer {

// Writes an augmented copy of the height x width x 3 frame `src` into `dst` (which may not
// alias it). Same (options, seed, src) -> same bytes. With options.enabled() false it copies.
void augment_frame(const uint8_t* src, uint8_t* dst, int32_t height, int32_t width,
                   const AugmentOptions& options, uint64_t seed);

// The seed of sample `index` at training step `step` (splitmix64 of both and the run's seed), so
// a resumed run draws what an uninterrupted one would.
uint64_t augment_seed(uint64_t run_seed, int64_t step, int64_t index);

}  // namespace tlvlink::trainer
