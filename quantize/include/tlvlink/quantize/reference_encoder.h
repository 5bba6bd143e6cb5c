#pragma once
// The reference edge touch encoder: a MobileNetV2-like network with *seeded random, untrained*
// weights, so the runtime, the tools and the boards can be tested and benchmarked before trained
// models exist. Its provenance says so (`training`: {"kind":"random-reference","seed":N}); its
// heads are random too, so its predictions mean nothing.
//
// Architecture (R = input resolution, 96..160; MACs at R=128 in brackets):
//   input [1,R,R,3] float -> stem 3x3/2 conv 16 + ReLU6
//   -> 8 inverted residuals (t = expansion, c = output channels, s = depthwise stride):
//      (1,16,1) (6,24,2) (6,24,1) (6,32,2) (6,32,1) (6,48,2) (6,48,1) (6,64,1)
//      each: 1x1 expand + ReLU6 (t > 1), 3x3 depthwise + ReLU6, 1x1 project (linear),
//      residual Add when stride 1 and channels match
//   -> 1x1 conv to 256 + ReLU6 -> GlobalAveragePool -> Reshape [1,256] -> FC to the embedding.
//   ~37.5 MMAC at 128 px (21 at 96, 59 at 160).
//
//   ReferenceEncoderOptions o;
//   o.dtype = EncoderDType::kInt8;
//   o.preprocess = my_preprocess;   // the deployment preprocessing (tools/io/preprocess.h)
//   auto enc = build_reference_encoder(o);   // Result<ReferenceEncoder>; enc->file is a .tlvm

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/metadata.h"

namespace tlvlink::quantize {

inline constexpr int32_t kMinEncoderResolution = 96;
inline constexpr int32_t kMaxEncoderResolution = 160;

enum class EncoderDType : uint8_t { kFloat32 = 0, kInt8 = 1 };

// Turns an 8-bit RGB frame (height x width x 3, interleaved) into graph input 0 ([1,H,W,C]
// float) exactly as inference does. Injected so calibration and golden inputs go through the
// deployment preprocessing without this library depending on the tools.
using FramePreprocessor = std::function<Result<std::vector<float>>(
    std::span<const uint8_t> rgb, int32_t height, int32_t width, const InputSpec& spec)>;

struct ReferenceEncoderOptions {
  int32_t resolution = 128;     // kMinEncoderResolution..kMaxEncoderResolution
  uint64_t seed = 1;            // weights, heads, calibration and golden frames
  int32_t embedding_dim = 128;  // 8..1024
  EncoderDType dtype = EncoderDType::kFloat32;
  int32_t calibration_frames = 16;     // int8 only: synthetic frames for min/max calibration
  int32_t golden_pairs = 2;            // embedded golden I/O pairs (0..8)
  FramePreprocessor preprocess;        // required
  bool log_activation_ranges = false;  // print per-layer activation ranges (stderr) once
};

struct LayerMacs {
  std::string name;
  uint64_t macs = 0;
};

struct ReferenceEncoder {
  std::vector<std::byte> file;    // the .tlvm bytes (loads with Model::load)
  uint64_t macs = 0;              // multiply-accumulates per frame
  std::vector<LayerMacs> layers;  // per conv / FC layer
};

Result<ReferenceEncoder> build_reference_encoder(const ReferenceEncoderOptions& options);

// MACs of the architecture at a resolution, without building it.
uint64_t reference_encoder_macs(int32_t resolution, int32_t embedding_dim = 128);

// A deterministic synthetic tactile frame (RGB, height x width x 3): smooth illumination
// gradients, a few soft contact blobs, sensor noise. Same seed, same bytes, on every platform.
std::vector<uint8_t> synthetic_touch_frame(int32_t height, int32_t width, uint64_t seed);

}  // namespace tlvlink::quantize
