#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "checkpoint.h is internal to tools/trainer: include its public headers instead"
#endif
// Checkpoints (internal, libtorch): one file written with torch::serialize::OutputArchive,
// holding
//   "meta"                JSON string: format tag, settings (options_to_json), arch, input
//                         normalisation, text encoder, teacher, dataset fingerprint, progress
//   "student"             EncoderNet parameters and BatchNorm buffers
//   "logit_scale"         the learnable log(1 / temperature)
//   "teacher_embeddings"  [n_train, D_t] frozen teacher outputs (absent without curriculum)
//   "projection"          TorchScript teacher D_t -> D projection (absent when D_t == D)
//   "supervised"          supervised heads (supervised.h; absent for objective tlv-link)
//   "optimizer"           AdamW state (moments, step counts)
// Written to PATH.tmp and renamed, so a crash never leaves a half-written checkpoint at PATH.

#include <torch/optim/optimizer.h>

#include <nlohmann/json.hpp>
#include <string>

#include "net.h"
#include "supervised.h"
#include "tlvlink/error.h"

namespace tlvlink::trainer {

inline constexpr const char* kCheckpointFormat = "tlvlink-trainer-checkpoint";
inline constexpr int kCheckpointVersion = 1;

struct TrainState {
  nlohmann::ordered_json meta;
  EncoderNet student{nullptr};
  torch::Tensor logit_scale;
  torch::Tensor teacher_embeddings;       // undefined without curriculum
  torch::nn::Linear projection{nullptr};  // null unless a TorchScript teacher needs one
  SupervisedHeads heads{nullptr};         // null unless the objective has a supervised term
};

Status save_checkpoint(const std::string& path, const TrainState& state,
                       const torch::optim::Optimizer* optimizer);

// Reads the meta and rebuilds the student (and projection) from it. Errors name the file: not
// a checkpoint, wrong format tag or version, weights that do not fit the recorded architecture.
Result<TrainState> load_checkpoint(const std::string& path);

// Restores the optimizer state saved with the checkpoint into `optimizer` (built over the same
// parameters in the same order).
Status load_optimizer_state(const std::string& path, torch::optim::Optimizer& optimizer);

// The architecture a checkpoint's meta records.
Result<ArchSpec> arch_from_meta(const nlohmann::ordered_json& meta);

}  // namespace tlvlink::trainer
