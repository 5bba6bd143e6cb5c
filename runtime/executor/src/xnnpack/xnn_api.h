#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error "xnn_api.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// The seam between tlvlink and XNNPACK's subgraph API. Every call into XNNPACK (initialize,
// subgraph, define_*, runtime, thread pool) goes through this header and xnn_api.cc, which is
// written against Debian's Feb-2022 snapshot (xnn_create_runtime_v2, xnn_define_add2, ...).
// Adopting a newer XNNPACK means rewriting xnn_api.cc, not the executor.
//
// <xnnpack.h> is deliberately not included here: the rest of the executor speaks tlvlink types.
// Every failure comes back as an Error (kBackend) naming the node, the XNNPACK call and the status.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "tlvlink/error.h"

struct xnn_subgraph;
struct xnn_runtime;
struct pthreadpool;

namespace tlvlink::xnn {

inline constexpr uint32_t kInvalidValueId = UINT32_MAX;  // == XNN_INVALID_VALUE_ID
// XNNPACK kernels may read (never write) this many bytes past the end of an input.
inline constexpr size_t kExtraBytes = 16;  // == XNN_EXTRA_BYTES

// What a call was made for, so its error can name it: "operator 'stem' (#0)".
struct NodeRef {
  const char* kind = "operator";  // "operator", "tensor", "runtime"
  std::string_view name;
  int32_t index = -1;
};

enum class ValueType : uint8_t { kFloat32, kQInt8, kQInt32, kQCInt8, kQCInt32 };

struct ValueDesc {
  ValueType type = ValueType::kFloat32;
  std::span<const size_t> dims;
  // Per-tensor quantization (kQInt8, kQInt32).
  float scale = 1.0f;
  int32_t zero_point = 0;
  // Per-channel quantization (kQCInt8, kQCInt32). XNNPACK keeps the pointer: the scales must
  // outlive every runtime created from the subgraph.
  std::span<const float> channel_scales;
  size_t channel_dim = 0;
  const void* data = nullptr;  // static data (same lifetime rule), or nullptr
  uint32_t external_id = kInvalidValueId;
  bool external_input = false;
  bool external_output = false;
};

struct Conv2DSpec {
  uint32_t pad_top = 0, pad_right = 0, pad_bottom = 0, pad_left = 0;
  uint32_t kernel_h = 1, kernel_w = 1;
  uint32_t stride_h = 1, stride_w = 1;
  uint32_t dilation_h = 1, dilation_w = 1;
  uint32_t groups = 1;               // convolution only
  size_t group_input_channels = 0;   // convolution: per group; depthwise: input channels
  size_t group_output_channels = 0;  // convolution only
  uint32_t depth_multiplier = 1;     // depthwise only
  float output_min = 0, output_max = 0;
  uint32_t input = kInvalidValueId, filter = kInvalidValueId, bias = kInvalidValueId;
  uint32_t output = kInvalidValueId;
};

struct MaxPool2DSpec {
  uint32_t pad_top = 0, pad_right = 0, pad_bottom = 0, pad_left = 0;
  uint32_t pool_h = 1, pool_w = 1;
  uint32_t stride_h = 1, stride_w = 1;
  float output_min = 0, output_max = 0;
  uint32_t input = kInvalidValueId, output = kInvalidValueId;
};

enum class BinaryKind : uint8_t { kAdd, kMultiply };

// Initializes XNNPACK once per process (thread-safe); later calls return the first outcome.
Status initialize();

// Owns an xnn_subgraph. Move-only.
class Subgraph {
 public:
  static Result<Subgraph> create(uint32_t external_value_ids);

  Result<uint32_t> define_value(const ValueDesc& desc, const NodeRef& who);
  Status define_convolution_2d(const Conv2DSpec& spec, const NodeRef& who);
  Status define_depthwise_convolution_2d(const Conv2DSpec& spec, const NodeRef& who);
  Status define_fully_connected(float output_min, float output_max, uint32_t input, uint32_t filter,
                                uint32_t bias, uint32_t output, const NodeRef& who);
  Status define_binary(BinaryKind kind, float output_min, float output_max, uint32_t input1,
                       uint32_t input2, uint32_t output, const NodeRef& who);
  Status define_clamp(float output_min, float output_max, uint32_t input, uint32_t output,
                      const NodeRef& who);
  Status define_sigmoid(uint32_t input, uint32_t output, const NodeRef& who);
  Status define_convert(uint32_t input, uint32_t output, const NodeRef& who);
  Status define_constant_pad(std::span<const size_t> before, std::span<const size_t> after,
                             float value, uint32_t input, uint32_t output, const NodeRef& who);
  Status define_reshape(std::span<const size_t> new_shape, uint32_t input, uint32_t output,
                        const NodeRef& who);
  Status define_resize_bilinear_2d(size_t new_height, size_t new_width, bool align_corners,
                                   uint32_t input, uint32_t output, const NodeRef& who);
  Status define_global_average_pooling_2d(float output_min, float output_max, uint32_t input,
                                          uint32_t output, const NodeRef& who);
  Status define_max_pooling_2d(const MaxPool2DSpec& spec, const NodeRef& who);

  xnn_subgraph* get() const { return handle_.get(); }

 private:
  struct Deleter {
    void operator()(xnn_subgraph* s) const;
  };
  explicit Subgraph(xnn_subgraph* s) : handle_(s) {}
  std::unique_ptr<xnn_subgraph, Deleter> handle_;
};

// Owns a pthreadpool; threads == 1 means no pool (XNNPACK runs on the caller's thread).
class ThreadPool {
 public:
  static Result<ThreadPool> create(int threads);
  pthreadpool* get() const { return handle_.get(); }

 private:
  struct Deleter {
    void operator()(pthreadpool* p) const;
  };
  explicit ThreadPool(pthreadpool* p) : handle_(p) {}
  std::unique_ptr<pthreadpool, Deleter> handle_;
};

struct ExternalBinding {
  uint32_t id;
  void* data;  // must stay valid (and carry kExtraBytes of slack) for the runtime's lifetime
};

// Owns an xnn_runtime. Borrows the thread pool passed to create(): the pool must outlive it.
class Runtime {
 public:
  // Operators are created and weights packed here. The subgraph may be deleted afterwards.
  // `who` names the graph in errors (the executor passes an operator when it diagnoses one).
  static Result<Runtime> create(const Subgraph& subgraph, const ThreadPool& pool,
                                const NodeRef& who = NodeRef{"runtime", {}, -1});
  Status setup(std::span<const ExternalBinding> externals);
  Status invoke();

 private:
  struct Deleter {
    void operator()(xnn_runtime* r) const;
  };
  explicit Runtime(xnn_runtime* r) : handle_(r) {}
  std::unique_ptr<xnn_runtime, Deleter> handle_;
};

}  // namespace tlvlink::xnn
