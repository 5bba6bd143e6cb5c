#pragma once
// Helpers for the reference-executor tests: byte conversions, running a model once, and the
// real-valued int8 oracle "dequantize -> float op -> quantize" the int8 kernels are held to.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/random.h"
#include "support/test_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::reference_test {

using quantize::ModelBuilder;
using quantize::QuantSpec;
using testing::Rng;

// The executors this build has (tests that state an exact expected value run on each).
#ifdef TLVLINK_HAVE_XNNPACK
inline constexpr ExecutorKind kAllExecutors[] = {ExecutorKind::kReference, ExecutorKind::kXnnpack};
#else
inline constexpr ExecutorKind kAllExecutors[] = {ExecutorKind::kReference};
#endif

// Float-vs-int8 oracle: the kernels scale in float and round half to even; the oracle works
// in double, so a value within float rounding of a .5 tie may land one step away.
inline constexpr int kInt8Tolerance = 1;

struct QParams {
  float scale = 1.0f;
  int32_t zero_point = 0;
  QuantSpec spec() const { return QuantSpec::per_tensor(scale, zero_point); }
  double real(int32_t q) const { return (q - zero_point) * static_cast<double>(scale); }
};

template <typename T>
std::vector<std::byte> to_bytes(const std::vector<T>& v) {
  std::vector<std::byte> b(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(b.data(), v.data(), b.size());
  return b;
}
template <typename T>
std::vector<T> from_bytes(std::span<const std::byte> b) {
  std::vector<T> v(b.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), b.data(), v.size() * sizeof(T));
  return v;
}

// Loads `file`, runs the reference executor (or `kind`) once on `inputs` (raw bytes per graph
// input) and returns every graph output. Records a gtest failure and returns {} on any error.
std::vector<std::vector<std::byte>> run_reference(const std::vector<std::byte>& file,
                                                  const std::vector<std::vector<std::byte>>& inputs,
                                                  ExecutorKind kind = ExecutorKind::kReference);

// Convenience: one input, one output of types In / Out.
template <typename Out, typename In>
std::vector<Out> run1(const std::vector<std::byte>& file, const std::vector<In>& input,
                      ExecutorKind kind = ExecutorKind::kReference) {
  auto out = run_reference(file, {to_bytes(input)}, kind);
  return out.empty() ? std::vector<Out>() : from_bytes<Out>(out[0]);
}

// real -> int8 with round half to even in double, clamped to [lo, hi] (quantized bounds).
int8_t quantize_double(double real, QParams q, int32_t lo = -128, int32_t hi = 127);
// Quantized bounds of a fused activation on an output with parameters q.
int32_t activation_qmin(Activation a, QParams q);
int32_t activation_qmax(Activation a, QParams q);

// Every element within `tolerance`; failures name the first few bad indices. Returns the count
// of exact matches (reported by tests as an agreement figure).
size_t expect_int8_near(const std::vector<int8_t>& actual, const std::vector<int8_t>& expected,
                        int tolerance, const std::string& what);

// Whether `value` occurs in v (rail checks).
bool contains(const std::vector<int8_t>& v, int8_t value);

}  // namespace tlvlink::reference_test
