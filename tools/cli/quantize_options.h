#pragma once
// Flags shared by `quantize` and `quantize-sweep`: where calibration frames come from, how many,
// the seed, and the moving-average constant; plus calibration with a progress line.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "cli/quantize_data.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::cli {

struct QuantizeCommonFlags {
  std::string calib;
  std::string calib_format = "auto";
  std::string calib_split = "all";
  int64_t calib_count = 200;
  int64_t heldout_count = 50;
  uint64_t seed = 1;
  double averaging_constant = quantize::TensorObserver::kDefaultAveragingConstant;

  void add_to(CLI::App& app);
  CalibDataOptions data_options(bool progress) const;
};

// quantize::calibrate over in-memory frames with a "quantize: calibrating" progress line.
Result<quantize::CalibrationStats> calibrate_with_progress(
    const Model& model, const std::vector<std::vector<float>>& frames,
    const QuantizeCommonFlags& flags, bool progress);

}  // namespace tlvlink::cli
