#pragma once
// A small graph using every operator type, as an fp32 model or as an int8 model
// (Quantize ... Dequantize), for the executor and no-allocation tests.

#include <cstddef>
#include <vector>

namespace tlvlink::reference_test {

// Input [1, 8, 8, 4] float32, output [1, 3] float32 (sigmoid of an FC).
// Conv -> depthwise conv -> MaxPool -> Add -> Mul (broadcast constant) -> Clamp -> Pad ->
// ResizeBilinear -> GlobalAveragePool -> Reshape -> FullyConnected -> Sigmoid.
std::vector<std::byte> all_ops_model(bool int8);
inline constexpr size_t kAllOpsInputElements = 8 * 8 * 4;
inline constexpr size_t kAllOpsOutputElements = 3;

}  // namespace tlvlink::reference_test
