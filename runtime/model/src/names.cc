#include <limits>

#include "tlvlink/graph.h"

namespace tlvlink {

const char* dtype_name(DType dtype) {
  switch (dtype) {
    case DType::kFloat32: return "float32";
    case DType::kInt8: return "int8";
    case DType::kInt32: return "int32";
    case DType::kUInt8: return "uint8";
  }
  return "unknown";
}

size_t dtype_size(DType dtype) {
  switch (dtype) {
    case DType::kFloat32: return 4;
    case DType::kInt8: return 1;
    case DType::kInt32: return 4;
    case DType::kUInt8: return 1;
  }
  return 0;
}

const char* op_type_name(OpType type) {
  switch (type) {
    case OpType::kConv2D: return "Conv2D";
    case OpType::kFullyConnected: return "FullyConnected";
    case OpType::kAdd: return "Add";
    case OpType::kMul: return "Mul";
    case OpType::kClamp: return "Clamp";
    case OpType::kSigmoid: return "Sigmoid";
    case OpType::kGlobalAveragePool: return "GlobalAveragePool";
    case OpType::kMaxPool2D: return "MaxPool2D";
    case OpType::kPad: return "Pad";
    case OpType::kReshape: return "Reshape";
    case OpType::kResizeBilinear: return "ResizeBilinear";
    case OpType::kQuantize: return "Quantize";
    case OpType::kDequantize: return "Dequantize";
  }
  return "Unknown";
}

float activation_min(Activation a) {
  return a == Activation::kNone ? -std::numeric_limits<float>::infinity() : 0.0f;
}

float activation_max(Activation a) {
  switch (a) {
    case Activation::kRelu6: return 6.0f;
    default: return std::numeric_limits<float>::infinity();
  }
}

}  // namespace tlvlink
