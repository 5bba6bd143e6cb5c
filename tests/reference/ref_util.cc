#include "reference/ref_util.h"

#include <algorithm>
#include <cstdlib>

#include "tlvlink/quant_math.h"

namespace tlvlink::reference_test {

std::vector<std::vector<std::byte>> run_reference(const std::vector<std::byte>& file,
                                                  const std::vector<std::vector<std::byte>>& inputs,
                                                  ExecutorKind kind) {
  auto model = testing::load_model(file);
  if (model == nullptr) return {};
  auto exec = make_executor(*model, kind, ExecutorOptions{});
  if (!exec.ok()) {
    ADD_FAILURE() << "make_executor(" << executor_kind_name(kind)
                  << "): " << exec.error().message();
    return {};
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    std::span<std::byte> in = (*exec)->input(i);
    EXPECT_EQ(in.size(), inputs[i].size()) << "input " << i;
    if (in.size() != inputs[i].size()) return {};
    std::memcpy(in.data(), inputs[i].data(), in.size());
  }
  const Status s = (*exec)->invoke();
  if (!s.ok()) {
    ADD_FAILURE() << "invoke: " << s.error().message();
    return {};
  }
  std::vector<std::vector<std::byte>> outputs;
  for (size_t i = 0; i < model->graph().outputs.size(); ++i) {
    const auto o = (*exec)->output(i);
    outputs.emplace_back(o.begin(), o.end());
  }
  return outputs;
}

int8_t quantize_double(double real, QParams q, int32_t lo, int32_t hi) {
  const double scaled = std::clamp(real / static_cast<double>(q.scale), -1e9, 1e9);
  const auto v = static_cast<int64_t>(std::nearbyint(scaled)) + q.zero_point;
  return static_cast<int8_t>(std::clamp<int64_t>(v, lo, hi));
}

int32_t activation_qmin(Activation a, QParams q) {
  return quantized_min(activation_min(a), q.scale, q.zero_point);
}
int32_t activation_qmax(Activation a, QParams q) {
  return quantized_max(activation_max(a), q.scale, q.zero_point);
}

size_t expect_int8_near(const std::vector<int8_t>& actual, const std::vector<int8_t>& expected,
                        int tolerance, const std::string& what) {
  EXPECT_EQ(actual.size(), expected.size()) << what;
  size_t exact = 0, reported = 0;
  for (size_t i = 0; i < std::min(actual.size(), expected.size()); ++i) {
    const int diff = std::abs(int{actual[i]} - int{expected[i]});
    if (diff == 0) ++exact;
    if (diff > tolerance && reported++ < 5) {
      ADD_FAILURE() << what << ": element " << i << " is " << int{actual[i]} << ", expected "
                    << int{expected[i]} << " (tolerance " << tolerance << " LSB)";
    }
  }
  return exact;
}

bool contains(const std::vector<int8_t>& v, int8_t value) {
  return std::find(v.begin(), v.end(), value) != v.end();
}

}  // namespace tlvlink::reference_test
