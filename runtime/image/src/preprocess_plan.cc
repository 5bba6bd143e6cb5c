#include <algorithm>
#include <cmath>
#include <cstring>

#include "resize_taps.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::image {

Result<InputEncoding> input_encoding(const Tensor& input) {
  if (input.dtype == DType::kFloat32) return InputEncoding{};
  TLV_ENSURE(input.dtype == DType::kInt8 && input.quant.quantized() && !input.quant.per_channel(),
             ErrorCode::kModelUnsupported,
             "model input '%.*s' is %s; frames can feed float32 or per-tensor int8 inputs",
             static_cast<int>(input.name.size()), input.name.data(), dtype_name(input.dtype));
  return InputEncoding{DType::kInt8, input.quant.scale[0], input.quant.zero_point[0]};
}

Result<PreprocessPlan> PreprocessPlan::create(const InputSpec& spec, int32_t frame_width,
                                              int32_t frame_height, int32_t frame_channels,
                                              InputEncoding encoding) {
  TLV_ENSURE(!spec.background_subtraction, ErrorCode::kModelUnsupported,
             "the model asks for background subtraction, which the tools do not implement yet");
  // A frame that does not fit the model is bad data (exit 1), not a bad argument.
  TLV_ENSURE(frame_channels == 1 || frame_channels == 3, ErrorCode::kShapeMismatch,
             "image has %d channels (1 or 3 supported)", frame_channels);
  TLV_ENSURE(frame_width >= 1 && frame_height >= 1, ErrorCode::kShapeMismatch,
             "image of %dx%d pixels", frame_width, frame_height);
  TLV_ENSURE(spec.height >= 1 && spec.width >= 1 && spec.channels >= 1 && spec.channels <= 3 &&
                 spec.mean.size() >= static_cast<size_t>(spec.channels) &&
                 spec.std.size() >= static_cast<size_t>(spec.channels),
             ErrorCode::kModelInvalidMetadata, "input spec %dx%dx%d with %zu means, %zu stds",
             spec.height, spec.width, spec.channels, spec.mean.size(), spec.std.size());
  TLV_ENSURE(
      encoding.dtype == DType::kFloat32 || (encoding.dtype == DType::kInt8 && encoding.scale > 0),
      ErrorCode::kInvalidArgument, "preprocessing can write float32 or int8, not %s",
      dtype_name(encoding.dtype));
  PreprocessPlan p;
  p.frame_width_ = frame_width;
  p.frame_height_ = frame_height;
  p.frame_channels_ = frame_channels;
  p.height_ = spec.height;
  p.width_ = spec.width;
  p.channels_ = spec.channels;
  p.order_ = spec.channel_order;
  p.filter_ = spec.resize_filter;
  p.encoding_ = encoding;
  p.outputs_finite_ = true;
  for (int32_t c = 0; c < spec.channels; ++c) {
    p.mean_[c] = spec.mean[static_cast<size_t>(c)];
    p.std_[c] = spec.std[static_cast<size_t>(c)];
    // The extremes of (v / 255 - mean) / std: v = 0 and v = 255 (gray mixes stay inside).
    for (float v : {0.0f, 255.0f}) {
      p.outputs_finite_ = p.outputs_finite_ && std::isfinite((v / 255.0f - p.mean_[c]) / p.std_[c]);
    }
  }
  int32_t src_w = frame_width, src_h = frame_height;
  if (spec.crop_w > 0) {
    TLV_ENSURE(
        spec.crop_x + spec.crop_w <= frame_width && spec.crop_y + spec.crop_h <= frame_height,
        ErrorCode::kShapeMismatch, "crop %d,%d %dx%d does not fit the %dx%d image", spec.crop_x,
        spec.crop_y, spec.crop_w, spec.crop_h, frame_width, frame_height);
    p.crop_x_ = spec.crop_x;
    p.crop_y_ = spec.crop_y;
    src_w = spec.crop_w;
    src_h = spec.crop_h;
  }
  // Area shrinks only; enlarging (on either axis) falls back to bilinear.
  if (p.filter_ == ResizeFilter::kArea && (p.height_ > src_h || p.width_ > src_w)) {
    p.filter_ = ResizeFilter::kBilinear;
  }
  p.rows_.resize(static_cast<size_t>(p.height_));
  p.cols_.resize(static_cast<size_t>(p.width_));
  const auto fill = [&](std::vector<Tap>& taps, int32_t in_len, int32_t out_len, int32_t off) {
    switch (p.filter_) {
      case ResizeFilter::kNearest:
        for (int32_t o = 0; o < out_len; ++o) {
          taps[static_cast<size_t>(o)].i0 =
              off + std::min(in_len - 1, static_cast<int32_t>((o + 0.5) * in_len / out_len));
        }
        break;
      case ResizeFilter::kArea:
        for (int32_t o = 0; o < out_len; ++o) {
          const int32_t a = o * in_len / out_len;
          taps[static_cast<size_t>(o)] = {off + a,
                                          off + std::max(a + 1, (o + 1) * in_len / out_len), 0};
        }
        break;
      case ResizeFilter::kBilinear:
        for (int32_t o = 0; o < out_len; ++o)
          taps[static_cast<size_t>(o)] = detail::bilinear_tap(in_len, out_len, o, off);
        break;
    }
  };
  fill(p.rows_, src_h, p.height_, p.crop_y_);
  fill(p.cols_, src_w, p.width_, p.crop_x_);
  p.identity_ = p.filter_ == ResizeFilter::kBilinear && src_h == p.height_ && src_w == p.width_;
  return p;
}

size_t PreprocessPlan::output_values() const {
  return static_cast<size_t>(height_) * static_cast<size_t>(width_) *
         static_cast<size_t>(channels_);
}

size_t PreprocessPlan::output_bytes() const {
  return output_values() * (encoding_.dtype == DType::kInt8 ? 1 : sizeof(float));
}

// The resized pixel (y, x) as the staged reference computes it: a uint8 per channel (bilinear
// rounds half away from zero, area rounds the mean).
void PreprocessPlan::resized_values(const ImageView& f, int32_t y, int32_t x, uint8_t v[3]) const {
  const Tap& r = rows_[static_cast<size_t>(y)];
  const Tap& c = cols_[static_cast<size_t>(x)];
  if (filter_ == ResizeFilter::kArea && !identity_ && frame_channels_ == 3) {
    // Every frame of the board and the tools takes this path (the models shrink RGB by area):
    // detail::area_value's box sums, the three channels walked at once by row pointers (the
    // same integer arithmetic, so the same bytes).
    uint32_t sum[3] = {0, 0, 0};
    for (int32_t sy = r.i0; sy < r.i1; ++sy) {
      const uint8_t* p = f.row(sy) + static_cast<size_t>(c.i0) * 3;
      for (int32_t sx = c.i0; sx < c.i1; ++sx, p += 3) {
        sum[0] += p[0];
        sum[1] += p[1];
        sum[2] += p[2];
      }
    }
    const auto n = static_cast<uint32_t>((r.i1 - r.i0) * (c.i1 - c.i0));
    for (size_t k = 0; k < 3; ++k) v[k] = static_cast<uint8_t>((sum[k] + n / 2) / n);
    return;
  }
  for (int32_t k = 0; k < frame_channels_; ++k) {
    if (identity_ || filter_ == ResizeFilter::kNearest) {
      v[k] = f.at(r.i0, c.i0, k);
    } else if (filter_ == ResizeFilter::kArea) {
      v[k] = detail::area_value(f, r, c, k);
    } else {
      v[k] = detail::bilinear_value(f, r, c, k);
    }
  }
}

template <typename Out>
void PreprocessPlan::run_typed(const ImageView& frame, Out* out) const {
  const auto channels = static_cast<size_t>(channels_);
  const auto store = [&](size_t i, float value) {
    if constexpr (std::is_same_v<Out, float>) {
      out[i] = value;
    } else {
      out[i] = quantize_value(value, encoding_.scale, encoding_.zero_point);
    }
  };
  size_t i = 0;
  for (int32_t y = 0; y < height_; ++y) {
    for (int32_t x = 0; x < width_; ++x, i += channels) {
      uint8_t v[3];
      resized_values(frame, y, x, v);
      float gray = 0;
      if (order_ == ChannelOrder::kGray) {
        const bool rgb = frame_channels_ == 3;
        const auto r = static_cast<float>(v[0]), g = static_cast<float>(v[rgb ? 1 : 0]),
                   b = static_cast<float>(v[rgb ? 2 : 0]);
        gray = 0.299f * r + 0.587f * g + 0.114f * b;
      }
      for (size_t c = 0; c < channels; ++c) {  // a gray frame feeds every channel
        const size_t source = frame_channels_ == 1 ? 0 : order_ == ChannelOrder::kBGR ? 2 - c : c;
        const float value = order_ == ChannelOrder::kGray ? gray : static_cast<float>(v[source]);
        store(i + c, (value / 255.0f - mean_[c]) / std_[c]);
      }
    }
  }
}

Status PreprocessPlan::check(const ImageView& f, size_t out_bytes) const {
  TLV_ENSURE(f.pixels != nullptr && f.width == frame_width_ && f.height == frame_height_ &&
                 f.channels == frame_channels_,
             ErrorCode::kShapeMismatch,
             "frame is %dx%dx%d; the preprocessing was planned for %dx%dx%d", f.width, f.height,
             f.channels, frame_width_, frame_height_, frame_channels_);
  TLV_ENSURE(out_bytes == output_bytes(), ErrorCode::kShapeMismatch,
             "preprocessing writes %zu bytes (%dx%dx%d %s); the buffer has %zu", output_bytes(),
             height_, width_, channels_, dtype_name(encoding_.dtype), out_bytes);
  return {};
}

Status PreprocessPlan::run(const ImageView& frame, std::span<std::byte> out) const {
  TLV_TRY(check(frame, out.size()));
  if (encoding_.dtype == DType::kInt8) {
    run_typed(frame, reinterpret_cast<int8_t*>(out.data()));
  } else {
    run_typed(frame, reinterpret_cast<float*>(out.data()));
  }
  return {};
}

Status PreprocessPlan::resize(const ImageView& frame, std::span<uint8_t> out) const {
  const size_t channels = static_cast<size_t>(frame_channels_);
  const size_t need = static_cast<size_t>(height_) * static_cast<size_t>(width_) * channels;
  TLV_ENSURE(frame.pixels != nullptr && frame.width == frame_width_ &&
                 frame.height == frame_height_ && frame.channels == frame_channels_,
             ErrorCode::kShapeMismatch,
             "frame is %dx%dx%d; the preprocessing was planned for %dx%dx%d", frame.width,
             frame.height, frame.channels, frame_width_, frame_height_, frame_channels_);
  TLV_ENSURE(out.size() == need, ErrorCode::kShapeMismatch,
             "resized frame is %zu bytes (%dx%dx%zu); the buffer has %zu", need, width_, height_,
             channels, out.size());
  size_t i = 0;
  for (int32_t y = 0; y < height_; ++y) {
    for (int32_t x = 0; x < width_; ++x, i += channels) {
      uint8_t v[3];
      resized_values(frame, y, x, v);
      for (size_t k = 0; k < channels; ++k) out[i + k] = v[k];
    }
  }
  return {};
}

Status PreprocessPlan::run(const ImageView& frame, std::span<float> out) const {
  TLV_ENSURE(encoding_.dtype == DType::kFloat32, ErrorCode::kInvalidArgument,
             "this preprocessing plan writes int8");
  TLV_TRY(check(frame, out.size_bytes()));
  run_typed(frame, out.data());
  return {};
}

}  // namespace tlvlink::image
