// Allocating conveniences over the plan, for host tools.
#include "resize_taps.h"
#include "tlvlink/image/preprocess.h"

namespace tlvlink::image {

Result<std::vector<float>> preprocess(const ImageView& image, const InputSpec& spec) {
  TLV_ASSIGN_OR_RETURN(const PreprocessPlan plan,
                       PreprocessPlan::create(spec, image.width, image.height, image.channels));
  std::vector<float> out(plan.output_values());
  TLV_TRY(plan.run(image, std::span<float>(out)));
  return out;
}

Result<std::vector<float>> preprocess(const Image& image, const InputSpec& spec) {
  return preprocess(image.view(), spec);
}

Image resize_bilinear(const Image& in, int32_t height, int32_t width) {
  if (in.height == height && in.width == width) return in;
  Image out{width, height, in.channels, {}};
  out.pixels.resize(static_cast<size_t>(width) * static_cast<size_t>(height) *
                    static_cast<size_t>(in.channels));
  const ImageView src = in.view();
  size_t i = 0;
  for (int32_t y = 0; y < height; ++y) {
    const detail::ResizeTap r = detail::bilinear_tap(in.height, height, y, 0);
    for (int32_t x = 0; x < width; ++x) {
      const detail::ResizeTap c = detail::bilinear_tap(in.width, width, x, 0);
      for (int32_t k = 0; k < in.channels; ++k)
        out.pixels[i++] = detail::bilinear_value(src, r, c, k);
    }
  }
  return out;
}

Result<Image> resize(const ImageView& image, int32_t height, int32_t width, ResizeFilter filter) {
  InputSpec spec;
  spec.height = height;
  spec.width = width;
  spec.channels = image.channels;
  spec.resize_filter = filter;
  const std::vector<float> mean(3, 0.0f), std(3, 1.0f);
  spec.mean = mean;
  spec.std = std;
  TLV_ASSIGN_OR_RETURN(const PreprocessPlan plan,
                       PreprocessPlan::create(spec, image.width, image.height, image.channels));
  Image out{width, height, image.channels, {}};
  out.pixels.resize(static_cast<size_t>(width) * static_cast<size_t>(height) *
                    static_cast<size_t>(image.channels));
  TLV_TRY(plan.resize(image, out.pixels));
  return out;
}

}  // namespace tlvlink::image
