#pragma once
// The validated in-memory form of a model graph. Everything here is a view into the bytes a
// Model owns: spans and string_views stay valid for the Model's lifetime. The loader builds it
// only after every check in runtime/model/src/validate_*.cc has passed, so executors may rely
// on the invariants stated below without re-checking them.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

namespace tlvlink {

enum class DType : uint8_t { kFloat32 = 0, kInt8 = 1, kInt32 = 2, kUInt8 = 3 };
const char* dtype_name(DType dtype);
size_t dtype_size(DType dtype);

// Up to kMaxRank dimensions, all >= 1 (validated).
struct Shape {
  static constexpr size_t kMaxRank = 6;
  std::array<int32_t, kMaxRank> dims{};
  size_t rank = 0;

  int32_t operator[](size_t i) const { return dims[i]; }
  size_t elements() const;
  bool operator==(const Shape& other) const;
};

struct QuantParams {
  std::span<const float> scale;         // empty: not quantized
  std::span<const int32_t> zero_point;  // same length as scale (validated)
  int32_t axis = -1;                    // -1 per-tensor

  bool quantized() const { return !scale.empty(); }
  bool per_channel() const { return axis >= 0; }
};

struct Tensor {
  std::string_view name;
  DType dtype = DType::kFloat32;
  Shape shape;
  QuantParams quant;
  std::span<const std::byte> data;  // empty for activations; 16-byte aligned constants

  bool is_constant() const { return !data.empty(); }
  size_t bytes() const { return shape.elements() * dtype_size(dtype); }
};

enum class OpType : uint8_t {
  kConv2D = 0,
  kFullyConnected,
  kAdd,
  kMul,
  kClamp,
  kSigmoid,
  kGlobalAveragePool,
  kMaxPool2D,
  kPad,
  kReshape,
  kResizeBilinear,
  kQuantize,
  kDequantize,
};
const char* op_type_name(OpType type);

enum class Activation : uint8_t { kNone = 0, kRelu, kRelu6 };
// Real-valued bounds of a fused activation (kNone: -inf..+inf).
float activation_min(Activation a);
float activation_max(Activation a);

struct Conv2DParams {
  int32_t kernel_h = 1, kernel_w = 1;
  int32_t stride_h = 1, stride_w = 1;
  int32_t dilation_h = 1, dilation_w = 1;
  int32_t pad_top = 0, pad_bottom = 0, pad_left = 0, pad_right = 0;
  int32_t groups = 1;
  Activation activation = Activation::kNone;
};
struct FullyConnectedParams {
  Activation activation = Activation::kNone;
};
struct BinaryParams {
  Activation activation = Activation::kNone;
};
struct ClampParams {
  float min = 0, max = 0;
};
struct Pool2DParams {
  int32_t pool_h = 1, pool_w = 1;
  int32_t stride_h = 1, stride_w = 1;
  int32_t pad_top = 0, pad_bottom = 0, pad_left = 0, pad_right = 0;
};
struct PadParams {
  std::array<int32_t, Shape::kMaxRank> before{};
  std::array<int32_t, Shape::kMaxRank> after{};
  float value = 0;
};
struct ResizeBilinearParams {
  bool align_corners = false;
};
struct NoParams {};

using OpParams = std::variant<NoParams, Conv2DParams, FullyConnectedParams, BinaryParams,
                              ClampParams, Pool2DParams, PadParams, ResizeBilinearParams>;

// Tensor index meaning "input not present" (e.g. a conv without bias).
inline constexpr int32_t kNoTensor = -1;

struct Operator {
  OpType type = OpType::kConv2D;
  std::string_view name;
  std::array<int32_t, 3> inputs{kNoTensor, kNoTensor, kNoTensor};
  size_t input_count = 0;
  int32_t output = kNoTensor;  // every op has exactly one output
  OpParams params;

  template <typename P>
  const P& get() const {
    return std::get<P>(params);
  }
};

// Invariants after loading: operators are topologically ordered; every activation is written by
// exactly one operator or is a graph input; every operator input index is in range and its
// producer precedes it; shapes are consistent with each op's semantics; quantization is valid.
struct Graph {
  std::vector<Tensor> tensors;
  std::vector<Operator> operators;
  std::vector<int32_t> inputs;
  std::vector<int32_t> outputs;

  const Tensor& tensor(int32_t index) const { return tensors[static_cast<size_t>(index)]; }
};

}  // namespace tlvlink
