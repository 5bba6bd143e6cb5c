#include "support/test_models.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "tlvlink/quant_math.h"

namespace tlvlink::testing {

namespace {
// Smallest per-channel weight scale: an all-zero channel still gets a normal, positive scale.
constexpr float kMinWeightScale = 0x1p-20f;
}  // namespace

std::unique_ptr<Model> load_model(const std::vector<std::byte>& file) {
  auto result = Model::load(file);
  if (!result.ok()) {
    ADD_FAILURE() << "model failed to load: " << error_code_name(result.error().code()) << ": "
                  << result.error().message();
    return nullptr;
  }
  return std::move(result).value();
}

Error load_error(const std::vector<std::byte>& file) {
  auto result = Model::load(file);
  return result.ok() ? Error() : result.error();
}

std::vector<std::byte> resealed(const std::vector<std::byte>& file) {
  const size_t body = file.size() >= kTrailerBytes ? file.size() - kTrailerBytes : 0;
  return seal_model(std::span<const std::byte>(file).first(body));
}

QuantizedWeights quantize_weights_per_channel(std::span<const float> weights,
                                              int32_t out_channels) {
  QuantizedWeights q;
  const size_t per = weights.size() / static_cast<size_t>(out_channels);
  q.values.resize(weights.size());
  q.scales.resize(static_cast<size_t>(out_channels));
  for (size_t c = 0; c < q.scales.size(); ++c) {
    float max_abs = 0;
    for (size_t i = 0; i < per; ++i) max_abs = std::max(max_abs, std::fabs(weights[c * per + i]));
    const float scale = std::max(max_abs / 127.0f, kMinWeightScale);
    q.scales[c] = scale;
    for (size_t i = 0; i < per; ++i) {
      const int32_t v = round_half_even(weights[c * per + i] / scale);
      q.values[c * per + i] = static_cast<int8_t>(std::clamp(v, kWeightMin, kInt8Max));
    }
  }
  return q;
}

std::vector<int32_t> quantize_bias(std::span<const float> bias, float input_scale,
                                   std::span<const float> weight_scales) {
  std::vector<int32_t> q(bias.size());
  for (size_t c = 0; c < bias.size(); ++c) {
    const double s = static_cast<double>(input_scale) *
                     static_cast<double>(weight_scales[weight_scales.size() == 1 ? 0 : c]);
    q[c] = static_cast<int32_t>(std::llround(static_cast<double>(bias[c]) / s));
  }
  return q;
}

}  // namespace tlvlink::testing
