#include "stability/stability_frames.h"

#include <cstdint>
#include <utility>

#include "tlvlink/sim/extreme.h"
#include "tlvlink/sim/renderer.h"

namespace tlvlink::testing {
namespace {

tools::Image filled(int32_t height, int32_t width, uint8_t value) {
  tools::Image im;
  im.height = height;
  im.width = width;
  im.channels = 3;
  im.pixels.assign(static_cast<size_t>(height) * static_cast<size_t>(width) * 3, value);
  return im;
}

// 0 / 255 squares of `cell` pixels: the largest local gradients an 8-bit frame can hold.
tools::Image checkerboard(int32_t height, int32_t width, int32_t cell) {
  tools::Image im = filled(height, width, 0);
  for (int32_t y = 0; y < height; ++y)
    for (int32_t x = 0; x < width; ++x)
      if (((y / cell) + (x / cell)) % 2 == 1)
        for (size_t c = 0; c < 3; ++c)
          im.pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                        3 +
                    c] = 255;
  return im;
}

tools::Image uniform_noise(int32_t height, int32_t width, uint64_t seed) {
  tools::Image im = filled(height, width, 0);
  uint64_t state = seed;
  for (uint8_t& p : im.pixels) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;  // LCG: same bytes everywhere
    p = static_cast<uint8_t>(state >> 56);
  }
  return im;
}

}  // namespace

Result<std::vector<NamedFrame>> stability_frames() {
  std::vector<NamedFrame> frames;
  for (const sim::ExtremeCase& c : sim::extreme_cases()) {
    auto renderer = sim::Renderer::create(c.sensor, /*sensor_seed=*/1);
    if (!renderer.ok()) return renderer.error();
    sim::Frame out;
    if (auto s = (*renderer)->render(c.scene, c.options, /*noise_seed=*/1, out); !s.ok()) {
      return Error::make(s.error().code(), "extreme case %.*s: %s", static_cast<int>(c.name.size()),
                         c.name.data(), s.error().message());
    }
    tools::Image im;
    im.height = out.height;
    im.width = out.width;
    im.channels = 3;
    im.pixels = std::move(out.rgb);
    frames.push_back({"sim:" + std::string(c.name), std::move(im)});
  }
  frames.push_back({"all-0", filled(240, 320, 0)});
  frames.push_back({"all-255", filled(240, 320, 255)});
  frames.push_back({"checkerboard-1px", checkerboard(240, 320, 1)});
  frames.push_back({"checkerboard-16px", checkerboard(240, 320, 16)});
  frames.push_back({"uniform-noise", uniform_noise(240, 320, 7)});
  tools::Image hot = filled(240, 320, 0);
  for (size_t c = 0; c < 3; ++c) hot.pixels[(120 * 320 + 160) * 3 + c] = 255;
  frames.push_back({"single-hot-pixel", std::move(hot)});
  frames.push_back({"tiny-2x2-noise", uniform_noise(2, 2, 11)});
  frames.push_back({"large-1080x1920-noise", uniform_noise(1080, 1920, 13)});
  return frames;
}

}  // namespace tlvlink::testing
