#include "tlvlink/image/resample.h"

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace tlvlink::image {
namespace {

// Destination rows are summed and rounded in blocks that stay in the L1 cache (a row of an
// 8 MP camera frame is 39 KB of floats).
constexpr size_t kBlock = 1024;

}  // namespace

Resampler::Taps Resampler::make_taps(int32_t src_len, int32_t dst_len, AxisMap map) {
  // Tent of half-width `support` source pixels, centred on the destination pixel's centre.
  const double support = std::max(1.0, map.scale);
  std::vector<std::vector<std::pair<int32_t, double>>> all(static_cast<size_t>(dst_len));
  Taps t;
  for (int32_t i = 0; i < dst_len; ++i) {
    const double s = map.offset + (i + 0.5) * map.scale - 0.5;  // in source pixel-centre units
    auto& taps = all[static_cast<size_t>(i)];
    double sum = 0;
    for (auto j = static_cast<int64_t>(std::ceil(s - support));
         j <= static_cast<int64_t>(std::floor(s + support)); ++j) {
      const double w = 1 - std::fabs(static_cast<double>(j) - s) / support;
      if (!(w > 0)) continue;
      // Outside the image: the edge pixel again (merged into its tap).
      const auto k = static_cast<int32_t>(std::clamp<int64_t>(j, 0, src_len - 1));
      if (!taps.empty() && taps.back().first == k) {
        taps.back().second += w;
      } else {
        taps.emplace_back(k, w);
      }
      sum += w;
    }
    if (taps.empty()) {  // cannot happen for support >= 1; keep the nearest pixel regardless
      taps.emplace_back(static_cast<int32_t>(std::clamp<double>(std::round(s), 0, src_len - 1)),
                        1.0);
      sum = 1;
    }
    for (auto& [k, w] : taps) w /= sum;
    t.max = std::max(t.max, static_cast<int32_t>(taps.size()));
  }
  t.first.resize(static_cast<size_t>(dst_len));
  t.count.resize(static_cast<size_t>(dst_len));
  t.weights.assign(static_cast<size_t>(dst_len) * static_cast<size_t>(t.max), 0.0f);
  for (int32_t i = 0; i < dst_len; ++i) {
    const auto& taps = all[static_cast<size_t>(i)];
    t.first[static_cast<size_t>(i)] = taps.front().first;
    t.count[static_cast<size_t>(i)] = static_cast<int32_t>(taps.size());
    for (size_t k = 0; k < taps.size(); ++k) {
      t.weights[static_cast<size_t>(i) * static_cast<size_t>(t.max) + k] =
          static_cast<float>(taps[k].second);
    }
  }
  return t;
}

void Resampler::plan(int32_t src_width, int32_t src_height, int32_t dst_width, int32_t dst_height,
                     AxisMap x_map, AxisMap y_map) {
  src_width_ = src_width;
  dst_width_ = dst_width;
  dst_height_ = dst_height;
  x_ = make_taps(src_width, dst_width, x_map);
  y_ = make_taps(src_height, dst_height, y_map);
  const size_t row = static_cast<size_t>(dst_width) * 3;
  ring_.assign(static_cast<size_t>(y_.max) * row, 0.0f);
  ring_row_.assign(static_cast<size_t>(y_.max), -1);
  acc_.assign(std::min(row, kBlock), 0.0f);
  rows_.assign(static_cast<size_t>(y_.max), nullptr);
}

void Resampler::horizontal(const uint8_t* src, float* out) const {
  const auto max = static_cast<size_t>(x_.max);
  for (int32_t x = 0; x < dst_width_; ++x) {
    const auto i = static_cast<size_t>(x);
    const float* w = x_.weights.data() + i * max;
    const uint8_t* p = src + static_cast<size_t>(x_.first[i]) * 3;
    float r = 0, g = 0, b = 0;
    for (int32_t t = 0; t < x_.count[i]; ++t, p += 3) {
      r += w[t] * p[0];
      g += w[t] * p[1];
      b += w[t] * p[2];
    }
    out[3 * i] = r;
    out[3 * i + 1] = g;
    out[3 * i + 2] = b;
  }
}

namespace {

[[gnu::noinline]] void scaled(float* __restrict out, const float* __restrict in, float k,
                              size_t n) {
  for (size_t i = 0; i < n; ++i) out[i] = k * in[i];
}

[[gnu::noinline]] void add_scaled(float* __restrict out, const float* __restrict in, float k,
                                  size_t n) {
  for (size_t i = 0; i < n; ++i) out[i] += k * in[i];
}

// Rounds to the nearest byte, clamped.
[[gnu::noinline]] void to_u8(const float* __restrict in, uint8_t* __restrict out, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    float v = in[i] + 0.5f;
    v = v > 0.0f ? v : 0.0f;
    v = v < 255.0f ? v : 255.0f;
    out[i] = static_cast<uint8_t>(v);
  }
}

// One destination row: sum over t of w[t] * rows[t][i] (in t order), rounded to bytes as to_u8
// does. With SSE2 in one pass, 16 elements at a time: GCC's own vectorisation of to_u8 emulates
// its compares with masks and took a quarter of a simulated 8 MP camera frame's time. Elsewhere
// (the boards) in cache-sized blocks of scaled / add_scaled / to_u8, which GCC vectorises.
// Either way every element is the same sum of the same products, so the bytes are the same.
void weighted_row(float* const* rows, const float* w, int32_t count, float* acc, uint8_t* out,
                  size_t n) {
  size_t i = 0;
#if defined(__SSE2__)
  const __m128 half = _mm_set1_ps(0.5f), zero = _mm_setzero_ps(), top = _mm_set1_ps(255.0f);
  const auto rounded = [&](__m128 sum) {
    return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(_mm_add_ps(sum, half), zero), top));
  };
  const auto store = [&](size_t at, __m128i a, __m128i b, __m128i c, __m128i d) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + at),
                     _mm_packus_epi16(_mm_packs_epi32(a, b), _mm_packs_epi32(c, d)));
  };
  if (count == 2) {  // enlarging (the simulator's camera frames): two rows per destination row
    const __m128 w0 = _mm_set1_ps(w[0]), w1 = _mm_set1_ps(w[1]);
    const float *r0 = rows[0], *r1 = rows[1];
    const auto lane = [&](size_t at) {
      return rounded(
          _mm_add_ps(_mm_mul_ps(w0, _mm_loadu_ps(r0 + at)), _mm_mul_ps(w1, _mm_loadu_ps(r1 + at))));
    };
    for (; i + 16 <= n; i += 16) store(i, lane(i), lane(i + 4), lane(i + 8), lane(i + 12));
  } else {
    const auto lane = [&](size_t at) {
      __m128 sum = _mm_mul_ps(_mm_set1_ps(w[0]), _mm_loadu_ps(rows[0] + at));
      for (int32_t t = 1; t < count; ++t)
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(w[t]), _mm_loadu_ps(rows[t] + at)));
      return rounded(sum);
    };
    for (; i + 16 <= n; i += 16) store(i, lane(i), lane(i + 4), lane(i + 8), lane(i + 12));
  }
#endif
  for (; i < n; i += kBlock) {
    const size_t m = std::min(kBlock, n - i);
    scaled(acc, rows[0] + i, w[0], m);
    for (int32_t t = 1; t < count; ++t) add_scaled(acc, rows[t] + i, w[t], m);
    to_u8(acc, out + i, m);
  }
}

}  // namespace

void Resampler::run(const uint8_t* src, uint8_t* dst) {
  run_strided(src, static_cast<size_t>(src_width_) * 3, dst);
}

void Resampler::run_strided(const uint8_t* src, size_t src_stride, uint8_t* dst) {
  const size_t row = static_cast<size_t>(dst_width_) * 3;
  const auto slots = static_cast<int32_t>(ring_row_.size());
  for (int32_t y = 0; y < dst_height_; ++y) {
    const auto i = static_cast<size_t>(y);
    const float* w = y_.weights.data() + i * static_cast<size_t>(y_.max);
    const int32_t count = y_.count[i];
    for (int32_t t = 0; t < count; ++t) {
      const int32_t r = y_.first[i] + t;
      const auto slot = static_cast<size_t>(r % slots);
      rows_[static_cast<size_t>(t)] = ring_.data() + slot * row;
      if (ring_row_[slot] != r) {
        horizontal(src + static_cast<size_t>(r) * src_stride, rows_[static_cast<size_t>(t)]);
        ring_row_[slot] = r;
      }
    }
    weighted_row(rows_.data(), w, count, acc_.data(), dst + i * row, row);
  }
  std::fill(ring_row_.begin(), ring_row_.end(), -1);  // the next frame has new pixels
}

}  // namespace tlvlink::image

namespace tlvlink::image {

AxisMap view_from_camera(double crop, int32_t camera_len, int32_t processed_len) {
  return {crop * camera_len, (1 - 2 * crop) * camera_len / processed_len};
}

}  // namespace tlvlink::image
