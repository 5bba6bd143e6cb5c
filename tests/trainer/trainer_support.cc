#include "trainer/trainer_support.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/npy_image.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/sets.h"

namespace tlvlink::trainer::testing {

Status write_touch_set(const std::string& dir, int32_t sessions, int32_t frames, uint64_t seed) {
  sim::TouchSetOptions gen;
  gen.sessions = sessions;
  gen.frames_per_session = frames;
  gen.vision_height = 60;
  gen.vision_width = 80;
  gen.seed = seed;
  TLV_ASSIGN_OR_RETURN(auto generator, sim::TouchSampleGenerator::create(gen));
  datasets::WriterOptions wo;
  wo.test_fraction = 0.25;
  wo.generator_json = sim::touch_set_options_json(gen);
  TLV_ASSIGN_OR_RETURN(auto writer, datasets::create_touch100k_writer(dir, wo));
  sim::TouchSample s;
  for (int64_t i = 0; i < generator->size(); ++i) {
    TLV_TRY(generator->generate(i, s));
    TLV_TRY(writer->write(s));
  }
  return writer->finish();
}

TrainOptions quick_options(const std::string& data_dir, const std::string& output) {
  TrainOptions o;
  o.data_dir = data_dir;
  o.output = output;
  o.arch = "tiny";
  o.input_height = 48;
  o.input_width = 64;
  o.batch = 8;
  o.epochs = 2;
  o.lr.lr = 1e-3;
  o.lr.warmup_steps = 2;
  o.teacher.epochs = 1;
  o.threads = 1;
  o.seed = 3;
  return o;
}

Result<std::vector<float>> preprocessed_frames(const std::string& data_dir, bool test_split,
                                               const InputSpec& spec, int64_t max_frames,
                                               int64_t& n) {
  std::ifstream sidecar(data_dir + "/" + datasets::kTouch100kSidecar);
  TLV_ENSURE(sidecar.good(), ErrorCode::kIo, "%s: no sidecar", data_dir.c_str());
  std::vector<float> out;
  n = 0;
  std::string line;
  while (std::getline(sidecar, line) && n < max_frames) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if ((j.at("split").get<std::string>() == "test") != test_split) continue;
    const std::string key = j.at("key").get<std::string>();
    TLV_ASSIGN_OR_RETURN(tools::Image image, tools::read_jpeg(data_dir + "/touch/" + key));
    TLV_ASSIGN_OR_RETURN(std::vector<float> x, image::preprocess(image, spec));
    out.insert(out.end(), x.begin(), x.end());
    ++n;
  }
  TLV_ENSURE(n > 0, ErrorCode::kInvalidArgument, "%s: no frames in the split", data_dir.c_str());
  return out;
}

Agreement compare_rows(std::span<const float> a, std::span<const float> b, int64_t rows) {
  Agreement g;
  const size_t dim = a.size() / static_cast<size_t>(rows);
  for (size_t r = 0; r < static_cast<size_t>(rows); ++r) {
    double dot = 0, na = 0, nb = 0;
    for (size_t i = 0; i < dim; ++i) {
      const auto x = static_cast<double>(a[r * dim + i]);
      const auto y = static_cast<double>(b[r * dim + i]);
      dot += x * y;
      na += x * x;
      nb += y * y;
      g.max_abs = std::max(g.max_abs, std::abs(x - y));
      g.max_magnitude = std::max(g.max_magnitude, std::abs(x));
    }
    g.min_cosine = std::min(g.min_cosine, dot / std::sqrt(na * nb));
  }
  return g;
}

}  // namespace tlvlink::trainer::testing
