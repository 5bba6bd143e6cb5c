// tlvlink gen-reference -o OUT.tlvm: writes the seeded random reference encoder (fp32 or int8).

#include <cinttypes>
#include <cstdio>

#include "common.h"
#include "tlvlink/io/file.h"
#include "tlvlink/quantize/frames.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::cli {
namespace {

struct GenOptions {
  std::string output;
  int resolution = 128;
  uint64_t seed = 1;
  int embedding_dim = 128;
  std::string dtype = "int8";
  int calibration_frames = 16;
  int golden = 2;
  bool print_ranges = false;
};

int run_gen(const GenOptions& o) {
  quantize::ReferenceEncoderOptions e;
  e.resolution = o.resolution;
  e.seed = o.seed;
  e.embedding_dim = o.embedding_dim;
  e.dtype = o.dtype == "int8" ? quantize::EncoderDType::kInt8 : quantize::EncoderDType::kFloat32;
  e.calibration_frames = o.calibration_frames;
  e.golden_pairs = o.golden;
  e.preprocess = quantize::deployment_preprocessor();
  e.log_activation_ranges = o.print_ranges;
  auto enc = quantize::build_reference_encoder(e);
  if (!enc.ok()) return report_error("gen-reference", enc.error());
  if (Status s = tools::write_file(o.output, enc->file); !s.ok())
    return report_error("gen-reference", s.error());
  std::printf(
      "wrote %s: reference encoder (random, untrained) %dx%d %s, embedding %d, seed %" PRIu64
      ", %.2f MMAC, %zu bytes, %d golden pairs\n",
      o.output.c_str(), o.resolution, o.resolution, o.dtype.c_str(), o.embedding_dim, o.seed,
      static_cast<double>(enc->macs) / 1e6, enc->file.size(), o.golden);
  return kExitOk;
}

}  // namespace

void add_gen_reference_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<GenOptions>();
  CLI::App* cmd = app.add_subcommand(
      "gen-reference",
      "Write the reference edge encoder: MobileNetV2-like, seeded random (untrained) weights, "
      "for testing and benchmarking");
  cmd->add_option("-o,--output", o->output, "Output model file (.tlvm)")->required();
  cmd->add_option("--resolution,-r", o->resolution, "Input height = width in pixels")
      ->check(CLI::Range(quantize::kMinEncoderResolution, quantize::kMaxEncoderResolution))
      ->capture_default_str();
  cmd->add_option("--seed,-s", o->seed, "Seed for weights, heads, calibration and golden frames")
      ->capture_default_str();
  cmd->add_option("--embedding-dim,-d", o->embedding_dim, "Embedding size")
      ->check(CLI::Range(8, 1024))
      ->capture_default_str();
  cmd->add_option("--dtype", o->dtype, "fp32, or int8 (post-training min/max calibration)")
      ->check(CLI::IsMember({"fp32", "int8"}))
      ->capture_default_str();
  cmd->add_option("--calib-frames,-k", o->calibration_frames, "Synthetic calibration frames (int8)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("--golden", o->golden, "Golden I/O pairs to embed")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  cmd->add_flag("--print-ranges", o->print_ranges,
                "Print per-layer activation ranges over the calibration frames");
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_gen(*o); });
}

}  // namespace tlvlink::cli
