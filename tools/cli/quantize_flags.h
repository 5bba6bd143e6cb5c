#pragma once
// Flags shared by `quantize` and `quantize-sweep`: where calibration frames come from, how many,
// the seed, and the moving-average constant.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "tlvlink/quantize/calib_data.h"
#include "tlvlink/quantize/observer.h"

namespace tlvlink::cli {

struct QuantizeDataFlags {
  std::vector<std::string> calib;  // --calib, repeatable: several sources share the counts
  std::string calib_images;        // --calib-images DIR: format images, explicitly
  std::string problems;            // --problems FILE: every load problem
  std::string calib_format = "auto";
  std::string calib_split = "all";
  int64_t calib_count = 200;
  int64_t heldout_count = 50;
  uint64_t seed = 1;
  double averaging_constant = quantize::TensorObserver::kDefaultAveragingConstant;

  void add_to(CLI::App& app);
  // Notes (an unreadable image skipped) go to stderr as "tlvlink quantize: skipping ...".
  quantize::CalibDataOptions options() const;
};

}  // namespace tlvlink::cli
