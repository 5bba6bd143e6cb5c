// The camera-to-prediction path on one core, measured on recorded camera frames:
//   tlvlink_pipeline_bench --frames DIR [--make N] [--sensor gelsight-mini|digit]
//                          [--model M.tlvm] [--rounds 3] [--json OUT]
// --make renders N frames of the simulated sensor's raw camera output into DIR first (a press at
// varied places and forces, some without contact), as the Python peer reads them too
// (pipeline_vs_python.sh). Prints, per stage, median / p99 wall ms and median CPU ms per frame:
// JPEG decode at full size, at the DCT scale the pipeline uses, the entropy-decoding floor, a
// cropped scaled decode; decode + preprocess (scaled vs full); the whole per-frame path (decode,
// preprocess, encoder, heads: every frame encoded, no gating) and its frames/s; the encoder with
// and without the input scan, as a share of the sensor's frame period.
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "jpeg_floor.h"
#include "make_frames.h"
#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/model.h"
#include "tlvlink/pipeline/frame_processor.h"

namespace {

using namespace tlvlink;  // NOLINT: a benchmark program

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

struct Timing {
  std::string label;
  double median_ms = 0, p99_ms = 0, cpu_ms = 0, fps = 0;
};

// Runs step(i) over every frame `rounds` times after one warm-up pass.
Timing measure(const std::string& label, size_t frames, int rounds,
               const std::function<bool(size_t)>& step) {
  Timing t{label};
  for (size_t i = 0; i < frames; ++i)
    if (!step(i)) return t;
  std::vector<double> wall, cpu;
  const auto start = std::chrono::steady_clock::now();
  for (int r = 0; r < rounds; ++r) {
    for (size_t i = 0; i < frames; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpu_ms();
      step(i);
      cpu.push_back(cpu_ms() - c0);
      wall.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  }
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<double> sorted = wall;
  std::sort(sorted.begin(), sorted.end());
  std::sort(cpu.begin(), cpu.end());
  t.median_ms = sorted[sorted.size() / 2];
  t.p99_ms = sorted[std::min(sorted.size() - 1,
                             static_cast<size_t>(0.99 * static_cast<double>(sorted.size())))];
  t.cpu_ms = cpu[cpu.size() / 2];
  t.fps = static_cast<double>(wall.size()) / total_s;
  std::printf("%-46s median %8.3f ms  p99 %8.3f ms  CPU %8.3f ms  %8.1f frames/s\n", label.c_str(),
              t.median_ms, t.p99_ms, t.cpu_ms, t.fps);
  return t;
}

std::vector<std::vector<uint8_t>> load(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string p = e.path().string();
    if (p.ends_with(".jpg") || p.ends_with(".yuyv")) names.push_back(p);
  }
  std::sort(names.begin(), names.end());
  std::vector<std::vector<uint8_t>> frames;
  for (const std::string& n : names) {
    std::ifstream in(n, std::ios::binary);
    frames.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return frames;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir, sensor = "gelsight-mini", model_path = "firmware/models/touch-tiny-int8.tlvm",
                   json;
  int make = 0, rounds = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--frames")
      dir = argv[i + 1];
    else if (a == "--make")
      make = std::atoi(argv[i + 1]);
    else if (a == "--sensor")
      sensor = argv[i + 1];
    else if (a == "--model")
      model_path = argv[i + 1];
    else if (a == "--rounds")
      rounds = std::atoi(argv[i + 1]);
    else if (a == "--json")
      json = argv[i + 1];
    else
      return std::fprintf(stderr, "unknown option %s\n", a.c_str()), 2;
  }
  const capture::SensorModel* sm = capture::find_sensor_model(sensor);
  if (dir.empty() || sm == nullptr || rounds < 1) {
    std::fprintf(stderr,
                 "usage: %s --frames DIR [--make N] [--sensor gelsight-mini|digit] [--model M] "
                 "[--rounds R] [--json OUT]\n",
                 argv[0]);
    return 2;
  }
  if (make > 0) {
    if (Status s = bench::make_frames(sensor, dir, make); !s.ok())
      return std::fprintf(stderr, "make frames: %s\n", s.error().message()), 1;
  }
  const std::vector<std::vector<uint8_t>> frames = load(dir);
  if (frames.empty()) return std::fprintf(stderr, "%s: no .jpg / .yuyv frames\n", dir.c_str()), 1;
  // One core, as the comparison asks: pin to the CPU we are on.
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(static_cast<unsigned>(sched_getcpu()), &set);
  sched_setaffinity(0, sizeof set, &set);

  auto model = Model::load_file(model_path.c_str());
  if (!model.ok()) return std::fprintf(stderr, "%s\n", model.error().message()), 1;
  auto exec = make_executor(**model, ExecutorKind::kXnnpack, {.threads = 1});
  if (!exec.ok()) return std::fprintf(stderr, "%s\n", exec.error().message()), 1;
  const image::FrameFormat camera{sm->format, sm->width, sm->height, 0};
  const bool mjpeg = sm->format == image::PixelFormat::kMjpeg;
  std::printf("%zu %s frames of %dx%d (%s), %s; %d rounds, one core\n", frames.size(),
              sensor.c_str(), sm->width, sm->height, image::pixel_format_name(sm->format),
              model_path.c_str(), rounds);
  std::vector<Timing> rows;
  std::vector<uint8_t> rgb, view_rgb;
  if (mjpeg) {
    image::JpegDecoder dec;
    size_t mean_bytes = 0;
    for (const auto& f : frames) mean_bytes += f.size();
    std::printf(
        "mean MJPEG frame %zu bytes, restart interval %d MCUs (0: none, no parallel slices)\n",
        mean_bytes / frames.size(), bench::restart_interval(frames[0]));
    rgb.resize(static_cast<size_t>(sm->width) * static_cast<size_t>(sm->height) * 3);
    rows.push_back(
        measure("jpeg decode, full size (TurboJPEG)", frames.size(), rounds, [&](size_t i) {
          return dec.decode_rgb(frames[i], 1, rgb.data(), rgb.size(), 0, "bench").ok();
        }));
    rows.push_back(measure("jpeg decode, 1/8 DCT scale", frames.size(), rounds, [&](size_t i) {
      return dec.decode_rgb(frames[i], 8, rgb.data(), rgb.size(), 0, "bench").ok();
    }));
    rows.push_back(measure("jpeg entropy decoding only (the floor)", frames.size(), rounds,
                           [&](size_t i) { return bench::entropy_decode(frames[i]); }));
    const int32_t sw = image::jpeg_scaled_size(sm->width, 8),
                  sh = image::jpeg_scaled_size(sm->height, 8);
    const auto cx = static_cast<int32_t>(sm->view.crop * sw),
               cy = static_cast<int32_t>(sm->view.crop * sh);
    rows.push_back(measure(
        "jpeg decode, 1/8, only the view (libjpeg crop)", frames.size(), rounds, [&](size_t i) {
          return bench::cropped_decode(frames[i], 8, cx, cy, sw - 2 * cx, sh - 2 * cy, rgb);
        }));
  }
  const Metadata& meta = (*model)->metadata();
  const Graph& g = (*model)->graph();
  auto encoding = image::input_encoding(g.tensor(g.inputs[0]));
  auto plan =
      image::PreprocessPlan::create(meta.input, sm->view.width, sm->view.height, 3, *encoding);
  if (!plan.ok()) return std::fprintf(stderr, "%s\n", plan.error().message()), 1;
  auto decoder = image::FrameDecoder::create(camera, sm->view);
  image::SensorView full_view = sm->view;
  full_view.jpeg_scale_denominator = 1;
  auto full_decoder = image::FrameDecoder::create(camera, full_view);
  view_rgb.resize(decoder->output_bytes());
  const image::ImageView view{view_rgb.data(), sm->view.width, sm->view.height, 3, 0};
  Executor& e = **exec;
  rows.push_back(
      measure("decode + preprocess (pipeline's scale)", frames.size(), rounds, [&](size_t i) {
        return decoder->decode(frames[i], view_rgb, "bench").ok() &&
               plan->run(view, e.input(0)).ok();
      }));
  if (mjpeg) {
    rows.push_back(
        measure("decode + preprocess (full-size decode)", frames.size(), rounds, [&](size_t i) {
          return full_decoder->decode(frames[i], view_rgb, "bench").ok() &&
                 plan->run(view, e.input(0)).ok();
        }));
  }
  rows.push_back(measure("encoder, invoke() with the input scan", frames.size(), rounds,
                         [&](size_t) { return e.invoke().ok(); }));
  rows.push_back(measure("encoder, invoke_trusted_inputs()", frames.size(), rounds,
                         [&](size_t) { return e.invoke_trusted_inputs().ok(); }));
  pipeline::ProcessorOptions po;
  po.contact_gating = false;  // every frame encoded, as the Python peer does
  const pipeline::SensorSetup setup{"bench", sm->view.width,       sm->view.height, 3,
                                    -1,      std::string(sm->name)};
  auto processor = pipeline::FrameProcessor::create(**model, e, std::span(&setup, 1), po);
  if (!processor.ok()) return std::fprintf(stderr, "%s\n", processor.error().message()), 1;
  pipeline::FramePrediction out;
  uint64_t seq = 0;
  rows.push_back(measure("whole frame: decode, preprocess, encoder, heads", frames.size(), rounds,
                         [&](size_t i) {
                           pipeline::FrameTimes t;
                           t.capture_ns = static_cast<int64_t>(++seq) * 40'000'000;
                           return decoder->decode(frames[i], view_rgb, "bench").ok() &&
                                  (*processor)->process(0, seq, view, t, out).ok();
                         }));
  const double period_ms = 1000.0 / sm->fps;
  const Timing& enc = rows[rows.size() - 2];
  const Timing& whole = rows.back();
  std::printf(
      "frame period %.1f ms (%.0f fps): encoder %.1f %% of it, the whole frame %.1f %% (one "
      "core)\n",
      period_ms, sm->fps, 100 * enc.median_ms / period_ms, 100 * whole.median_ms / period_ms);
  if (!json.empty()) {
    std::ofstream o(json);
    o << "{\"sensor\":\"" << sensor << "\",\"frames\":" << frames.size() << ",\"rows\":[";
    for (size_t i = 0; i < rows.size(); ++i) {
      o << (i ? "," : "") << "{\"label\":\"" << rows[i].label
        << "\",\"median_ms\":" << rows[i].median_ms << ",\"p99_ms\":" << rows[i].p99_ms
        << ",\"cpu_ms\":" << rows[i].cpu_ms << ",\"fps\":" << rows[i].fps << "}";
    }
    o << "]}\n";
  }
  return 0;
}
