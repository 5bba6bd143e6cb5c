#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "teacher.h is internal to tools/trainer: include its public headers instead"
#endif
// The vision teacher of TLV-Link (internal, libtorch). It is frozen while the student trains and
// there is no augmentation, so its embedding of every training sample is computed once.
//  - built-in: a `builtin_arch` EncoderNet pre-trained from scratch on the paired vision images
//    against the same text features (CLIP loss, learnable temperature), then frozen.
//  - TorchScript: a user's vision encoder loaded with torch::jit::load, run in eval mode.

#include <cstdio>
#include <nlohmann/json.hpp>

#include "data_cache.h"
#include "net.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer {

struct TeacherOutput {
  torch::Tensor embeddings;           // [n, D_t] float, no grad
  nlohmann::ordered_json provenance;  // kind, arch / file, epochs, losses, seconds
};

// `text` is [n, D] (the student's targets); `log` may be null.
Result<TeacherOutput> pretrain_builtin_teacher(const DataCache& cache, const torch::Tensor& text,
                                               const TrainOptions& options, std::FILE* log);
Result<TeacherOutput> run_torchscript_teacher(const DataCache& cache, const TrainOptions& options);

}  // namespace tlvlink::trainer
