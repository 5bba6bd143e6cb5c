// A board program on the minimal runtime with image decoding (tests/minimal): a camera frame,
// MJPEG or YUYV, becomes the model's head predictions through runtime/image (FrameDecoder,
// PreprocessPlan), the executor and runtime/heads, with no allocation per frame.
//   tlvlink_board_frames MODEL.tlvm      exit 0: predictions finite, both formats agree with the
//                                        allocating host path, 0 allocations in the frame loop
// The frames are made here (a 640x480 camera, the synthetic gel image below) because a board
// program has no simulator. libjpeg-turbo mallocs its own per-image work memory inside each
// decode (the TurboJPEG API offers no way to keep it); this program counts tlvlink's own
// allocations (operator new, counted by tests/support/alloc_counter.cc), which must be zero.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "support/alloc_counter.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/image/convert.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/tlvlink.h"
#include "tlvlink/verify/compare.h"

namespace {

using namespace tlvlink;

constexpr int32_t kCameraWidth = 640, kCameraHeight = 480;
constexpr int32_t kViewWidth = 320, kViewHeight = 240;
constexpr int kWarmupFrames = 3, kCountedFrames = 30;

// A gel lit from three sides with a round imprint, at camera resolution.
std::vector<uint8_t> gel_frame(int32_t w, int32_t h) {
  std::vector<uint8_t> rgb(static_cast<size_t>(w) * static_cast<size_t>(h) * 3);
  for (int32_t y = 0; y < h; ++y) {
    for (int32_t x = 0; x < w; ++x) {
      const double dx = (x - 0.55 * w) / (0.12 * w), dy = (y - 0.5 * h) / (0.12 * w);
      const double press = std::exp(-(dx * dx + dy * dy));
      uint8_t* p =
          &rgb[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 3];
      p[0] = static_cast<uint8_t>(90 + 60.0 * x / w + 70 * press * dx);
      p[1] = static_cast<uint8_t>(110 + 50.0 * y / h + 40 * press);
      p[2] = static_cast<uint8_t>(140 - 40.0 * x / w - 60 * press * dy);
    }
  }
  return rgb;
}

// The embedding output as floats into `out` (int8 outputs dequantized). No allocation.
void embedding_floats(const Model& m, const Executor& e, std::vector<float>& out) {
  const Graph& g = m.graph();
  const auto o = static_cast<size_t>(std::max(m.metadata().embedding_output, 0));
  const Tensor& t = g.tensor(g.outputs[o]);
  for (size_t i = 0; i < out.size(); ++i) out[i] = verify::output_value(t, e.output(o), i);
}

struct FramePath {
  image::FrameDecoder decoder;
  image::PreprocessPlan plan;
  std::vector<uint8_t> view;  // the processed frame
};

int run(const char* path) {
  auto model = Model::load_file(path);
  if (!model.ok()) return std::printf("%s: %s\n", path, model.error().message()), 1;
  const Model& m = **model;
  const Graph& g = m.graph();
  // XNNPACK when this build has it (the minimal image build does), else the reference.
#if defined(TLVLINK_HAVE_XNNPACK)
  auto exec = make_executor(m, ExecutorKind::kXnnpack, {.threads = 1});
#else
  auto exec = make_executor(m, ExecutorKind::kReference, {});
#endif
  if (!exec.ok()) return std::printf("%s: %s\n", path, exec.error().message()), 1;
  Executor& e = **exec;
  auto heads = heads::HeadEvaluator::create(m.metadata());
  if (!heads.ok()) return std::printf("%s: %s\n", path, heads.error().message()), 1;
  auto encoding = image::input_encoding(g.tensor(g.inputs[0]));
  if (!encoding.ok()) return std::printf("%s: %s\n", path, encoding.error().message()), 1;

  // The camera's two formats, made from the same gel frame.
  const std::vector<uint8_t> gel = gel_frame(kCameraWidth, kCameraHeight);
  image::JpegEncoder encoder;
  auto jpeg_span = encoder.encode({gel.data(), kCameraWidth, kCameraHeight, 3, 0}, 90,
                                  image::JpegEncoder::Subsampling::k422);
  if (!jpeg_span.ok()) return std::printf("encode: %s\n", jpeg_span.error().message()), 1;
  const std::vector<uint8_t> jpeg(jpeg_span->begin(), jpeg_span->end());
  const image::FrameFormat yuyv_format{image::PixelFormat::kYuyv, kCameraWidth, kCameraHeight, 0};
  std::vector<uint8_t> yuyv(image::frame_bytes(yuyv_format));
  if (!image::upright_rgb_to_camera(gel, yuyv_format, image::Orientation::kUpright, yuyv).ok())
    return std::printf("yuyv conversion failed\n"), 1;

  const image::SensorView view{kViewWidth, kViewHeight, 0.0, image::Orientation::kUpright, 0};
  std::vector<float> embedding(static_cast<size_t>(m.metadata().embedding_dim));
  int failures = 0;
  struct Camera {
    const char* name;
    image::PixelFormat format;
    const std::vector<uint8_t>* bytes;
  };
  for (const Camera& cam : {Camera{"mjpeg", image::PixelFormat::kMjpeg, &jpeg},
                            Camera{"yuyv", image::PixelFormat::kYuyv, &yuyv}}) {
    const char* name = cam.name;
    const image::PixelFormat format = cam.format;
    const std::vector<uint8_t>* bytes = cam.bytes;
    const image::FrameFormat camera_format{format, kCameraWidth, kCameraHeight, 0};
    auto decoder = image::FrameDecoder::create(camera_format, view);
    auto plan =
        image::PreprocessPlan::create(m.metadata().input, kViewWidth, kViewHeight, 3, *encoding);
    if (!decoder.ok() || !plan.ok()) {
      std::printf("%s: %s\n", name, (!decoder.ok() ? decoder.error() : plan.error()).message());
      ++failures;
      continue;
    }
    std::vector<uint8_t> frame(decoder->output_bytes());
    size_t allocations = 0;
    bool ok = true;
    for (int i = 0; i < kWarmupFrames + kCountedFrames && ok; ++i) {
      if (i == kWarmupFrames) {
        testing::start_counting_allocations();
      }
      ok = decoder->decode(*bytes, frame, name).ok() &&
           plan->run({frame.data(), kViewWidth, kViewHeight, 3, 0}, e.input(0)).ok() &&
           e.invoke().ok();
      if (ok) embedding_floats(m, e, embedding);
      ok = ok && heads->evaluate(embedding).ok();
    }
    allocations = testing::stop_counting_allocations();
    bool finite = ok;
    for (const heads::HeadResult& r : heads->results()) {
      for (float p : r.probabilities) finite = finite && std::isfinite(p) && p >= 0 && p <= 1;
      const auto top = static_cast<size_t>(r.top);
      std::printf("%s head %-14.*s -> %-16.*s p=%.3f\n", name, static_cast<int>(r.name.size()),
                  r.name.data(), static_cast<int>(r.labels[top].size()), r.labels[top].data(),
                  static_cast<double>(r.probabilities[top]));
    }
    // The allocating host path (decode_jpeg at the decoder's DCT scale, which is the view's size
    // here, then preprocess) gives the same input tensor.
    bool same = true;
    if (format == image::PixelFormat::kMjpeg) {
      auto decoded = image::decode_jpeg(jpeg, name, decoder->jpeg_scale_denominator());
      auto x = decoded.ok() ? image::preprocess(*decoded, m.metadata().input)
                            : Result<std::vector<float>>(decoded.error());
      same = x.ok() && encoding->dtype == DType::kFloat32 &&
             std::memcmp(x->data(), e.input(0).data(), e.input(0).size()) == 0;
    }
    std::printf("%s: %d frames, %zu allocations in the last %d, predictions %s, host path %s\n",
                name, kWarmupFrames + kCountedFrames, allocations, kCountedFrames,
                finite ? "finite" : "NOT FINITE", same ? "identical" : "DIFFERS");
    failures += (ok && finite && same && allocations == 0) ? 0 : 1;
  }
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s MODEL.tlvm\n", argv[0]);
    return 2;
  }
  const int failures = run(argv[1]);
  std::printf("board frames: %s\n", failures == 0 ? "PASS" : "FAIL");
  return failures == 0 ? 0 : 1;
}
