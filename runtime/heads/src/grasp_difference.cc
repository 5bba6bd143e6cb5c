#include "tlvlink/heads/grasp_difference.h"

#include <algorithm>
#include <cmath>

namespace tlvlink::heads {
namespace {

constexpr int32_t kChannels = 3;
constexpr int32_t kRadius = 4;  // 9 taps: the Gaussian beyond 3.3 sigma is under 0.5 % of its peak
constexpr float kSigma = 1.2f;
constexpr float kRawThresholds[] = {5.5f, 15.5f, 30.5f};
constexpr float kBlurThresholds[] = {3.0f, 8.0f, 15.0f, 30.0f};

const std::array<float, 2 * kRadius + 1>& gaussian_taps() {
  static const std::array<float, 2 * kRadius + 1> taps = [] {
    std::array<float, 2 * kRadius + 1> t{};
    float sum = 0;
    for (int32_t i = -kRadius; i <= kRadius; ++i) {
      t[static_cast<size_t>(i + kRadius)] =
          std::exp(-static_cast<float>(i * i) / (2 * kSigma * kSigma));
      sum += t[static_cast<size_t>(i + kRadius)];
    }
    for (float& v : t) v /= sum;
    return t;
  }();
  return taps;
}

// Mirrored index (OpenCV's BORDER_REFLECT_101: -1 -> 1, n -> n - 2); n >= 2.
int32_t mirror(int32_t i, int32_t n) {
  while (i < 0 || i >= n) i = i < 0 ? -i : 2 * (n - 1) - i;
  return i;
}

float signed_log1p(double v) { return static_cast<float>(v < 0 ? -std::log1p(-v) : std::log1p(v)); }

}  // namespace

InputSpec difference_input_spec(const InputSpec& model_input) {
  static constexpr float kZero[4] = {0, 0, 0, 0};
  static constexpr float kUnit[4] = {1 / 255.0f, 1 / 255.0f, 1 / 255.0f, 1 / 255.0f};
  InputSpec spec = model_input;
  const auto n = static_cast<size_t>(std::clamp(model_input.channels, 1, 4));
  spec.mean = std::span<const float>(kZero, n);
  spec.std = std::span<const float>(kUnit, n);
  return spec;
}

Result<GraspDifference> GraspDifference::create(int32_t height, int32_t width, int32_t channels) {
  TLV_ENSURE(channels == kChannels, ErrorCode::kModelUnsupported,
             "grasp difference features need 3-channel input, the model reads %d", channels);
  TLV_ENSURE(height >= 2 && width >= 2 && height <= 4096 && width <= 4096,
             ErrorCode::kInvalidArgument, "grasp difference of %dx%d images (2..4096 each side)",
             width, height);
  GraspDifference g;
  g.height_ = height;
  g.width_ = width;
  g.values_ = static_cast<size_t>(height) * static_cast<size_t>(width) * kChannels;
  g.d_.assign(g.values_, 0.0f);
  g.blurred_.assign(g.values_, 0.0f);
  constexpr int32_t taps = 2 * kRadius + 1;
  g.tap_columns_.resize(static_cast<size_t>(width) * taps);
  g.tap_rows_.resize(static_cast<size_t>(height) * taps);
  for (int32_t x = 0; x < width; ++x)
    for (int32_t t = -kRadius; t <= kRadius; ++t)
      g.tap_columns_[static_cast<size_t>(x * taps + t + kRadius)] =
          mirror(x + t, width) * kChannels;
  for (int32_t y = 0; y < height; ++y)
    for (int32_t t = -kRadius; t <= kRadius; ++t)
      g.tap_rows_[static_cast<size_t>(y * taps + t + kRadius)] = mirror(y + t, height);
  return g;
}

Status GraspDifference::compute(std::span<const float> before, std::span<const float> during,
                                std::span<float> out) {
  TLV_ENSURE(before.size() == values_ && during.size() == values_ &&
                 out.size() == static_cast<size_t>(kDifferenceFeatures),
             ErrorCode::kShapeMismatch,
             "grasp difference: before %zu, during %zu values (need %zu), out %zu (need %d)",
             before.size(), during.size(), values_, out.size(), kDifferenceFeatures);
  double sum_abs = 0, sum_sq = 0, channel_d[kChannels] = {};
  size_t raw_over[3] = {};
  for (size_t i = 0; i < values_; ++i) {
    const float d = during[i] - before[i];
    if (!std::isfinite(d)) {
      const bool in_before = !std::isfinite(before[i]);
      return Error::make(ErrorCode::kNonFiniteValue,
                         "grasp difference: the '%s' image holds %f at value %zu",
                         in_before ? "before" : "during",
                         static_cast<double>(in_before ? before[i] : during[i]), i);
    }
    d_[i] = d;
    const float a = std::fabs(d);
    sum_abs += static_cast<double>(a);
    sum_sq += static_cast<double>(d) * static_cast<double>(d);
    channel_d[i % kChannels] += static_cast<double>(d);
    for (size_t k = 0; k < 3; ++k) raw_over[k] += a > kRawThresholds[k] ? 1 : 0;
  }
  // Separable blur: rows into blurred_, then columns, each b = |G * d| counted as it comes. The
  // taps' mirrored sources come from the tables made by create().
  const auto& taps = gaussian_taps();
  constexpr size_t kTaps = 2 * kRadius + 1;
  const auto w = static_cast<size_t>(width_);
  for (int32_t y = 0; y < height_; ++y) {
    const float* row = d_.data() + static_cast<size_t>(y) * w * kChannels;
    float* dst = blurred_.data() + static_cast<size_t>(y) * w * kChannels;
    for (size_t x = 0; x < w; ++x) {
      const int32_t* source = tap_columns_.data() + x * kTaps;
      for (size_t c = 0; c < kChannels; ++c) {
        float acc = 0;
        for (size_t t = 0; t < kTaps; ++t) acc += taps[t] * row[static_cast<size_t>(source[t]) + c];
        dst[x * kChannels + c] = acc;
      }
    }
  }
  double sum_b = 0, channel_b[kChannels] = {};
  size_t blur_over[4] = {};
  const size_t stride = w * kChannels;
  const float* rows[kTaps];
  for (int32_t y = 0; y < height_; ++y) {
    for (size_t t = 0; t < kTaps; ++t) {
      rows[t] = blurred_.data() +
                static_cast<size_t>(tap_rows_[static_cast<size_t>(y) * kTaps + t]) * stride;
    }
    for (size_t i = 0; i < stride; ++i) {
      float acc = 0;
      for (size_t t = 0; t < kTaps; ++t) acc += taps[t] * rows[t][i];
      const float b = std::fabs(acc);
      sum_b += static_cast<double>(b);
      channel_b[i % kChannels] += static_cast<double>(b);
      for (size_t k = 0; k < 4; ++k) blur_over[k] += b > kBlurThresholds[k] ? 1 : 0;
    }
  }
  const auto n = static_cast<double>(values_);
  const double per_channel = n / kChannels;
  double s[kDifferenceFeatures] = {sum_abs / n, sum_sq / n};
  for (size_t k = 0; k < 3; ++k) s[2 + k] = static_cast<double>(raw_over[k]) / n;
  s[5] = sum_b / n;
  for (size_t k = 0; k < 4; ++k) s[6 + k] = static_cast<double>(blur_over[k]) / n;
  for (size_t c = 0; c < kChannels; ++c) {
    s[10 + c] = channel_d[c] / per_channel;
    s[13 + c] = channel_b[c] / per_channel;
  }
  for (size_t k = 0; k < static_cast<size_t>(kDifferenceFeatures); ++k) out[k] = signed_log1p(s[k]);
  return {};
}

}  // namespace tlvlink::heads
