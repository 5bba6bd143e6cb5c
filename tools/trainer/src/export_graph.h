#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "export_graph.h is internal to tools/trainer: include its public headers instead"
#endif
// The trained student as plain arrays (no libtorch) and its .tlvm graph: BatchNorm folded into
// each conv, ReLU6 fused into Conv2D / Add, NHWC activations and OHWI weights like the
// reference encoder (quantize/src/encoder/encoder_graph.cc).

#include <cstddef>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/quantize/model_builder.h"
#include "tlvlink/trainer/arch.h"
#include "tlvlink/trainer/fold.h"

namespace tlvlink::trainer {

struct PlainLayer {
  ConvShape shape;
  std::vector<float> weight_oihw;  // libtorch layout
  BatchNormParams bn;
};

struct PlainNet {
  ArchSpec arch;
  std::vector<PlainLayer> layers;  // one per arch.layers entry
  std::vector<float> fc_weight;    // [embedding_dim, channels]
  std::vector<float> fc_bias;      // [embedding_dim]
};

// Adds the graph to `builder` (input "input" [1,H,W,3] float, output "embedding" [1,D]) and
// returns its MACs. Errors: shapes that disagree with the architecture, folding failures.
Result<uint64_t> add_student_graph(const PlainNet& net, quantize::ModelBuilder& builder);

}  // namespace tlvlink::trainer
