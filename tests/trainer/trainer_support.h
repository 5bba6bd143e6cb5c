#pragma once
// Shared pieces of the trainer tests: temp directories, small simulator sets in the Touch100k
// layout, and the comparison figures of the parity checks.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "support/temp_dir.h"
#include "tlvlink/error.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer::testing {

using ::tlvlink::testing::TempDir;

// `sessions` x `frames` simulator samples written with the Touch100k writer (sidecar included,
// a quarter of the sessions in the test split), vision images 60x80 to keep it quick.
Status write_touch_set(const std::string& dir, int32_t sessions, int32_t frames, uint64_t seed);

// Training settings small enough for a unit test: `tiny` at 48x64, batch 8, a few steps.
TrainOptions quick_options(const std::string& data_dir, const std::string& output);

// The touch frames of a split, preprocessed for `spec` by tools::preprocess (the runtime's
// path): [n, H, W, 3] floats, and their count in `n`.
Result<std::vector<float>> preprocessed_frames(const std::string& data_dir, bool test_split,
                                               const InputSpec& spec, int64_t max_frames,
                                               int64_t& n);

struct Agreement {
  double min_cosine = 1;     // over rows
  double max_abs = 0;        // over all values
  double max_magnitude = 0;  // largest |value| of the reference
};
Agreement compare_rows(std::span<const float> reference, std::span<const float> other,
                       int64_t rows);

}  // namespace tlvlink::trainer::testing
