#pragma once
// Small float graphs with random data for the executor comparison tests.

#include <cstdint>
#include <vector>

#include "support/random.h"
#include "xnnpack/harness.h"

namespace tlvlink::testing {

struct ConvCase {
  int32_t n = 1, h = 8, w = 8, cin = 4, cout = 8;
  int32_t kh = 3, kw = 3, stride_h = 1, stride_w = 1, dilation_h = 1, dilation_w = 1;
  int32_t pad_top = 1, pad_bottom = 1, pad_left = 1, pad_right = 1;
  int32_t groups = 1;
  bool bias = true;
  Activation activation = Activation::kNone;
};
int32_t conv_output_size(int32_t in, int32_t k, int32_t stride, int32_t dilation, int32_t pad);

// input -> Conv2D -> output.
TGraph conv_graph(const ConvCase& c, Rng& rng);
// [n, cin] -> FullyConnected -> [n, cout].
TGraph fc_graph(int32_t n, int32_t cin, int32_t cout, bool bias, Activation act, Rng& rng);
// a (input), b (input or constant) -> Add/Mul -> output, numpy broadcasting.
TGraph binary_graph(OpType type, std::vector<int32_t> a_shape, std::vector<int32_t> b_shape,
                    bool b_constant, Activation act, Rng& rng);
// input [shape] -> op(params) -> output [out_shape].
TGraph unary_graph(OpType type, std::vector<int32_t> shape, std::vector<int32_t> out_shape,
                   OpParams params = NoParams{});
// Random small encoder block: conv -> (depthwise) -> add residual -> pool -> GAP -> FC.
TGraph random_chain(Rng& rng);
// A random conv case within the limits the randomized tests explore.
ConvCase random_conv_case(Rng& rng);

}  // namespace tlvlink::testing
