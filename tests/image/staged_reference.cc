// The deployment preprocessing as it was written before the plan/run API (tools/io/preprocess.cc
// at 7024ac8, verbatim but for the namespace): crop into a new image, resize into another,
// normalise into a vector. The shipped models were trained through this code; the plan must
// reproduce it bit for bit (preprocess_plan_test.cc).
#include "image/staged_reference.h"

#include <algorithm>
#include <cmath>

namespace tlvlink::testing::staged {
namespace {

using image::Image;

image::Image crop(const image::Image& in, const InputSpec& spec, bool& ok) {
  ok = spec.crop_x + spec.crop_w <= in.width && spec.crop_y + spec.crop_h <= in.height;
  if (!ok) return {};
  image::Image out{spec.crop_w, spec.crop_h, in.channels, {}};
  out.pixels.resize(static_cast<size_t>(out.width) * out.height * out.channels);
  size_t i = 0;
  for (int32_t y = 0; y < out.height; ++y)
    for (int32_t x = 0; x < out.width; ++x)
      for (int32_t c = 0; c < out.channels; ++c)
        out.pixels[i++] = in.at(spec.crop_y + y, spec.crop_x + x, c);
  return out;
}

image::Image resize_nearest(const image::Image& in, int32_t height, int32_t width) {
  image::Image out{width, height, in.channels, {}};
  out.pixels.resize(static_cast<size_t>(width) * height * in.channels);
  size_t i = 0;
  for (int32_t y = 0; y < height; ++y) {
    const int32_t sy =
        std::min(in.height - 1, static_cast<int32_t>((y + 0.5) * in.height / height));
    for (int32_t x = 0; x < width; ++x) {
      const int32_t sx = std::min(in.width - 1, static_cast<int32_t>((x + 0.5) * in.width / width));
      for (int32_t c = 0; c < in.channels; ++c) out.pixels[i++] = in.at(sy, sx, c);
    }
  }
  return out;
}

// Box filter: each output pixel averages the source pixels whose centres fall in its footprint
// (falls back to bilinear when enlarging, where a footprint may hold no centre).
image::Image resize_area(const image::Image& in, int32_t height, int32_t width) {
  if (height > in.height || width > in.width) return resize_bilinear(in, height, width);
  image::Image out{width, height, in.channels, {}};
  out.pixels.resize(static_cast<size_t>(width) * height * in.channels);
  size_t i = 0;
  for (int32_t y = 0; y < height; ++y) {
    const int32_t y0 = y * in.height / height, y1 = std::max(y0 + 1, (y + 1) * in.height / height);
    for (int32_t x = 0; x < width; ++x) {
      const int32_t x0 = x * in.width / width, x1 = std::max(x0 + 1, (x + 1) * in.width / width);
      for (int32_t c = 0; c < in.channels; ++c) {
        uint32_t sum = 0;
        for (int32_t sy = y0; sy < y1; ++sy)
          for (int32_t sx = x0; sx < x1; ++sx) sum += in.at(sy, sx, c);
        const uint32_t n = static_cast<uint32_t>((y1 - y0) * (x1 - x0));
        out.pixels[i++] = static_cast<uint8_t>((sum + n / 2) / n);
      }
    }
  }
  return out;
}

}  // namespace

image::Image resize_bilinear(const image::Image& in, int32_t height, int32_t width) {
  if (in.height == height && in.width == width) return in;
  image::Image out{width, height, in.channels, {}};
  out.pixels.resize(static_cast<size_t>(width) * height * in.channels);
  const float sy = static_cast<float>(in.height) / static_cast<float>(height);
  const float sx = static_cast<float>(in.width) / static_cast<float>(width);
  size_t i = 0;
  for (int32_t y = 0; y < height; ++y) {
    const float fy = std::clamp((static_cast<float>(y) + 0.5f) * sy - 0.5f, 0.0f,
                                static_cast<float>(in.height - 1));
    const auto y0 = static_cast<int32_t>(fy);
    const int32_t y1 = std::min(y0 + 1, in.height - 1);
    const float wy = fy - static_cast<float>(y0);
    for (int32_t x = 0; x < width; ++x) {
      const float fx = std::clamp((static_cast<float>(x) + 0.5f) * sx - 0.5f, 0.0f,
                                  static_cast<float>(in.width - 1));
      const auto x0 = static_cast<int32_t>(fx);
      const int32_t x1 = std::min(x0 + 1, in.width - 1);
      const float wx = fx - static_cast<float>(x0);
      for (int32_t c = 0; c < in.channels; ++c) {
        const float top =
            in.at(y0, x0, c) + wx * static_cast<float>(in.at(y0, x1, c) - in.at(y0, x0, c));
        const float bot =
            in.at(y1, x0, c) + wx * static_cast<float>(in.at(y1, x1, c) - in.at(y1, x0, c));
        out.pixels[i++] =
            static_cast<uint8_t>(std::lround(std::clamp(top + wy * (bot - top), 0.0f, 255.0f)));
      }
    }
  }
  return out;
}

Result<std::vector<float>> preprocess(const image::Image& img, const InputSpec& spec) {
  TLV_ENSURE(!spec.background_subtraction, ErrorCode::kModelUnsupported,
             "the model asks for background subtraction, which the tools do not implement yet");
  // A frame that does not fit the model is bad data (exit 1), not a bad argument.
  TLV_ENSURE(img.channels == 1 || img.channels == 3, ErrorCode::kShapeMismatch,
             "image has %d channels (1 or 3 supported)", img.channels);
  const image::Image* src = &img;
  image::Image cropped;
  if (spec.crop_w > 0) {
    bool ok = false;
    cropped = crop(img, spec, ok);
    TLV_ENSURE(ok, ErrorCode::kShapeMismatch, "crop %d,%d %dx%d does not fit the %dx%d image",
               spec.crop_x, spec.crop_y, spec.crop_w, spec.crop_h, img.width, img.height);
    src = &cropped;
  }
  const image::Image sized =
      spec.resize_filter == ResizeFilter::kNearest ? resize_nearest(*src, spec.height, spec.width)
      : spec.resize_filter == ResizeFilter::kArea  ? resize_area(*src, spec.height, spec.width)
                                                   : resize_bilinear(*src, spec.height, spec.width);
  const auto n = static_cast<size_t>(spec.height) * static_cast<size_t>(spec.width);
  const auto channels = static_cast<size_t>(spec.channels);
  std::vector<float> out(n * channels);
  for (size_t p = 0; p < n; ++p) {
    const uint8_t* px = &sized.pixels[p * static_cast<size_t>(sized.channels)];
    float rgb[3];
    if (sized.channels == 3) {
      rgb[0] = px[0];
      rgb[1] = px[1];
      rgb[2] = px[2];
    } else {
      rgb[0] = rgb[1] = rgb[2] = px[0];
    }
    for (size_t c = 0; c < channels; ++c) {
      float v;
      switch (spec.channel_order) {
        case ChannelOrder::kBGR: v = rgb[2 - c]; break;
        case ChannelOrder::kGray: v = 0.299f * rgb[0] + 0.587f * rgb[1] + 0.114f * rgb[2]; break;
        default: v = rgb[c]; break;
      }
      out[p * channels + c] = (v / 255.0f - spec.mean[c]) / spec.std[c];
    }
  }
  return out;
}

}  // namespace tlvlink::testing::staged
