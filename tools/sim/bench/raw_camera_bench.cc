// Raw camera timing on one core: the processed render alone, RawCamera::render (processed +
// periphery + resize to the raw size + encode), and RawDecoder::recover at each MJPEG decode
// scale. Prints the median, min and max wall ms and the median CPU ms over the frames (CPU time
// is what a shared, busy machine inflates least), the raw frame's size, and how close each
// scale's recovered frame is to the processed frame (mean |d|, PSNR).
//
//   tlvlink_raw_camera_bench [--sensor gelsight-mini] [--frames 20] [--quality 90]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "tlvlink/sim/raw_camera.h"

namespace {

using namespace tlvlink::sim;  // NOLINT: a benchmark program

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

// Runs `step(i)` for i in [0, frames) after one warm-up call and prints its timing.
bool measure(const char* label, int frames, const std::function<bool(int)>& step) {
  if (!step(-1)) return false;
  std::vector<double> wall, cpu;
  for (int i = 0; i < frames; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_ms();
    if (!step(i)) return false;
    cpu.push_back(cpu_ms() - c0);
    wall.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  const size_t mid = wall.size() / 2;
  std::printf("%-34s wall ms median %7.2f  min %7.2f  max %7.2f   CPU ms median %7.2f\n", label,
              wall[mid], wall.front(), wall.back(), cpu[mid]);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string sensor = "gelsight-mini";
  int frames = 20;
  RawOptions raw_options;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--sensor") == 0)
      sensor = argv[i + 1];
    else if (std::strcmp(argv[i], "--frames") == 0)
      frames = std::max(1, std::atoi(argv[i + 1]));
    else if (std::strcmp(argv[i], "--quality") == 0)
      raw_options.jpeg_quality = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: %s [--sensor NAME] [--frames N] [--quality Q]\n", argv[0]);
      return 2;
    }
  }
  auto profile = sensor_profile(sensor);
  if (!profile.ok()) {
    std::fprintf(stderr, "%s\n", profile.error().message());
    return 1;
  }
  auto renderer = Renderer::create(profile.value(), 1);
  auto camera = RawCamera::create(profile.value(), 1, raw_options);
  if (!renderer.ok() || !camera.ok()) {
    std::fprintf(stderr, "%s\n", (renderer.ok() ? camera.error() : renderer.error()).message());
    return 1;
  }
  // A textured 5 mm ball at 4 N with markers: a typical frame.
  ContactScene scene;
  scene.loading.force_n = 4;
  scene.texture.sq_um = 5;
  RenderOptions options;
  options.markers = true;
  const RawLayout& layout = (*camera)->layout();
  std::printf("%s: raw %s %dx%d, processed %dx%d, %d frames\n", sensor.c_str(),
              raw_format_name(layout.format), layout.width, layout.height, profile->width,
              profile->height, frames);
  Frame frame;
  bool ok = measure("processed render (Renderer)", frames, [&](int i) {
    return (*renderer)->render(scene, options, static_cast<uint64_t>(i + 2), frame).ok();
  });
  RawFrame raw;
  std::vector<size_t> sizes;
  ok = ok && measure("raw render + encode (RawCamera)", frames, [&](int i) {
         const bool done =
             (*camera)->render(scene, options, static_cast<uint64_t>(i + 2), raw).ok();
         sizes.push_back(raw.bytes.size());
         return done;
       });
  if (!ok) return 1;
  std::sort(sizes.begin(), sizes.end());
  std::printf("raw frame bytes: median %zu (min %zu, max %zu)\n", sizes[sizes.size() / 2],
              sizes.front(), sizes.back());
  const std::vector<int32_t> scales = layout.format == RawFormat::kMjpeg
                                          ? std::vector<int32_t>{8, 4, 2, 1}
                                          : std::vector<int32_t>{1};
  for (int32_t d : scales) {
    RecoverOptions ro;
    ro.jpeg_scale_denominator = d;
    auto decoder = RawDecoder::create(profile.value(), ro);
    if (!decoder.ok()) return 1;
    std::vector<uint8_t> rgb;
    char label[64];
    std::snprintf(label, sizeof label, "recover (decode 1/%d + crop/resize)", d);
    if (!measure(label, frames, [&](int) { return (*decoder)->recover(raw.bytes, rgb).ok(); }))
      return 1;
    // How close the recovered frame is to the processed one at this scale.
    double abs_sum = 0, sq_sum = 0;
    for (size_t i = 0; i < rgb.size(); ++i) {
      const double diff = static_cast<double>(rgb[i]) - raw.processed.rgb[i];
      abs_sum += std::fabs(diff);
      sq_sum += diff * diff;
    }
    const auto n = static_cast<double>(rgb.size());
    std::printf("    vs processed: mean |d| %.3f DN, PSNR %.2f dB\n", abs_sum / n,
                10 * std::log10(255.0 * 255.0 / std::max(sq_sum / n, 1e-12)));
  }
  return 0;
}
