#pragma once
// Can this configuration's model run here? Loads the model (full validation), creates the
// configured executor, runs the model's golden pairs on it, and builds the per-frame chain
// for the configured sensors and heads — everything Session::start does before it opens a
// camera. `tlvlinkd --verify` (the board package's install-time check) and `tlvlink strip` /
// `tlvlink flash` (a scene against a model, on the host) use it, so the board and the host
// apply one rule: a head the model lacks, or a sensor whose frames cannot feed the model's
// input, is an error naming the head or the sensor.

#include <memory>
#include <string>
#include <vector>

#include "tlvlink/daemon/config.h"
#include "tlvlink/error.h"
#include "tlvlink/model.h"

namespace tlvlink::daemon {

struct ModelCheck {
  std::string model_name;
  size_t golden_pairs = 0;
  bool golden_pass = false;             // every pair and the stored head outputs within tolerance
                                        // (false when there are no pairs)
  double max_error = 0, tolerance = 0;  // of the worst pair
  std::vector<std::string> reported_heads;  // per-frame heads the daemon would report
  std::string grasp_head;                   // empty: no grasp prediction
};

// The configuration's model, fully validated, and when `model_public_key` is set, its signature
// checked against that key (errors name the model and the key). Session::start and check_model
// both load through here.
Result<std::unique_ptr<Model>> load_config_model(const DaemonConfig& config);

// Errors: the model does not load (or its signature does not verify), the executor cannot be made,
// a golden pair cannot run, a head or a sensor does not fit (the context names the configuration).
// A golden mismatch is not an error: golden_pass is false.
Result<ModelCheck> check_model(const DaemonConfig& config);

}  // namespace tlvlink::daemon
