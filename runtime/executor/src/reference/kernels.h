#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error "kernels.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// Internals of the reference executor: the kernel interface shared by the op-family files.
// Kernels are plain loops over tensors the loader has validated (graph.h invariants), bound
// to their buffers once at executor creation, so they cannot fail and allocate nothing.

#include <array>
#include <cstddef>

#include "tlvlink/graph.h"

namespace tlvlink::reference {

// One operator's tensors and buffers, fixed at executor creation.
struct OpArgs {
  const Operator* op = nullptr;
  std::array<const Tensor*, 3> in{};          // nullptr: absent optional input (e.g. bias)
  std::array<const std::byte*, 3> in_data{};  // constant data or the activation's arena slot
  const Tensor* out = nullptr;
  std::byte* out_data = nullptr;

  template <typename T>
  const T* input(size_t i) const {
    return reinterpret_cast<const T*>(in_data[i]);
  }
  template <typename T>
  T* output() const {
    return reinterpret_cast<T*>(out_data);
  }
};

using Kernel = void (*)(const OpArgs& args);

// Kernel for an op of the family, chosen by its input dtype; nullptr when the reference
// executor has none for that combination (the caller reports it, naming the operator).
Kernel select_conv2d(const OpArgs& args);
Kernel select_fully_connected(const OpArgs& args);
Kernel select_elementwise(const OpArgs& args);  // Add, Mul, Clamp, Sigmoid
Kernel select_pooling(const OpArgs& args);      // GlobalAveragePool, MaxPool2D
Kernel select_pad_reshape(const OpArgs& args);  // Pad, Reshape
Kernel select_resize_bilinear(const OpArgs& args);
Kernel select_convert(const OpArgs& args);  // Quantize, Dequantize

}  // namespace tlvlink::reference
