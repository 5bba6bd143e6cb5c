#pragma once
#ifndef TLVLINK_EVAL_PRIVATE
#error "probe_json.h is internal to tools/eval: include its public headers instead"
#endif
// The view-penalty choice of a probe as JSON, for the heads' provenance and eval's report.

#include <nlohmann/json.hpp>

#include "tlvlink/eval/probe.h"

namespace tlvlink::eval::internal {

inline nlohmann::json view_trials_json(const FittedProbe& p) {
  nlohmann::json trials = nlohmann::json::array();
  for (const ViewWeightTrial& t : p.view_trials) {
    trials.push_back({{"view_weight", t.view_weight},
                      {"l2", t.l2},
                      {"validation_accuracy", t.accuracy},
                      {"validation_view_agreement", t.agreement}});
  }
  return trials;
}

}  // namespace tlvlink::eval::internal
