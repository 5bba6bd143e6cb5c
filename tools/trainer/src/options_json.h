#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "options_json.h is internal to tools/trainer: include its public headers instead"
#endif
// TrainOptions <-> JSON: recorded in every checkpoint (a resumed run takes its settings from
// there) and in the exported model's provenance.

#include <nlohmann/json.hpp>

#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer {

nlohmann::ordered_json options_to_json(const TrainOptions& options);
// Restores the settings that determine the result; paths of this run (data_dir, output,
// checkpoint_dir, log_path, resume) and threads are left as they are in `out`.
Status options_from_json(const nlohmann::ordered_json& j, TrainOptions& out);

// Deterministic shuffles: the order of epoch `epoch` depends only on (seed, epoch, n), so a
// resumed run continues with the same batches (splitmix64 + Fisher-Yates; identical everywhere).
std::vector<int64_t> epoch_order(int64_t n, uint64_t seed, int64_t epoch);

}  // namespace tlvlink::trainer
