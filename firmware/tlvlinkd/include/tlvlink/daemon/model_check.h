#pragma once
// Can this configuration's model run here? Loads the model (full validation), creates the
// configured executor, runs the model's golden pairs on it, and builds the per-frame chain
// for the configured sensors and heads — everything Session::start does before it opens a
// camera. `tlvlinkd --verify` (the board package's install-time check) and `tlvlink strip` /
// `tlvlink flash` (a scene against a model, on the host) use it, so the board and the host
// apply one rule: a head the model lacks, or a sensor whose frames cannot feed the model's
// input, is an error naming the head or the sensor.

#include <string>
#include <vector>

#include "tlvlink/daemon/config.h"
#include "tlvlink/error.h"

namespace tlvlink::daemon {

struct ModelCheck {
  std::string model_name;
  size_t golden_pairs = 0;
  bool golden_pass = false;  // every pair within tolerance (false when there are none)
  double max_error = 0, tolerance = 0;  // of the worst pair
  std::vector<std::string> reported_heads;  // per-frame heads the daemon would report
  std::string grasp_head;                   // empty: no grasp prediction
};

// Errors: the model does not load, the executor cannot be made, a golden pair cannot run,
// a head or a sensor does not fit (the context names the configuration). A golden mismatch
// is not an error: golden_pass is false.
Result<ModelCheck> check_model(const DaemonConfig& config);

}  // namespace tlvlink::daemon
