// The pipeline driven by replayed Feel-style grasp episodes (the simulator's grasp generator):
// each finger's frames go through contact gating, preprocessing, the shipped int8 encoder and
// the grasp tracker with the controller's "closed" / "lifting" marks. Every grasp prediction must
// be exactly the model's grasp head on the episode's before and during frames, computed here
// independently (preprocess, invoke, the difference statistics of the model's crop and resize in
// DN, sigmoid(w . f + b)): the board predicts what eval scores.
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/executor.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/heads/grasp_difference.h"
#include "tlvlink/heads/head_math.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/model.h"
#include "tlvlink/pipeline/frame_processor.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::pipeline {
namespace {

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kPeriod = 40 * kMs;  // a Mini at 25 fps

image::ImageView view_of(const sim::RgbImage& f) { return {f.rgb.data(), f.width, f.height, 3, 0}; }

// The embedding of one frame, the way eval computes it (allocating host path).
std::vector<float> embed(const Model& m, Executor& e, const sim::RgbImage& f) {
  auto x = image::preprocess(view_of(f), m.metadata().input);
  EXPECT_TRUE(x.ok());
  std::memcpy(e.input(0).data(), x->data(), e.input(0).size());
  EXPECT_TRUE(e.invoke().ok());
  const Graph& g = m.graph();
  const auto o = static_cast<size_t>(m.metadata().embedding_output);
  const std::span<const std::byte> b = e.output(o);
  std::vector<float> out(static_cast<size_t>(m.metadata().embedding_dim));
  std::memcpy(out.data(), b.data(), out.size() * sizeof(float));
  EXPECT_EQ(g.tensor(g.outputs[o]).dtype, DType::kFloat32);
  return out;
}

TEST(PipelineFeelReplay, GraspPredictionsAreTheGraspHeadOnTheEpisodesFrames) {
  auto model = Model::load_file(TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm");
  ASSERT_TRUE(model.ok()) << model.error().message();
  const Model& m = **model;
  auto exec = make_executor(m, ExecutorKind::kXnnpack, {});
  auto check_exec = make_executor(m, ExecutorKind::kXnnpack, {});
  ASSERT_TRUE(exec.ok() && check_exec.ok());
  sim::GraspSetOptions go;
  go.objects = 3;
  go.grasps_per_object = 2;
  go.vision_height = 24;
  go.vision_width = 32;
  go.seed = 11;
  auto gen = sim::GraspEpisodeGenerator::create(go);
  ASSERT_TRUE(gen.ok()) << gen.error().message();
  ProcessorOptions po;
  po.grasp_options.mode = GraspOptions::Mode::kCommanded;
  po.grasp_options.settle_ns = 100 * kMs;
  po.contact.reference_frames = 5;
  sim::GraspEpisode ep;
  ASSERT_TRUE((*gen)->generate(0, ep).ok());
  const int32_t w = ep.frames[0][0].width, h = ep.frames[0][0].height;
  // The episodes are GelSight Mini grasps (the generator's default sensor): the fingers say so,
  // and the processor uses the model's Mini grasp head.
  const SensorSetup sensors[2] = {{"A", w, h, 3, 0, "gelsight-mini"},
                                  {"B", w, h, 3, 1, "gelsight-mini"}};
  auto p = FrameProcessor::create(m, **exec, sensors, po);
  ASSERT_TRUE(p.ok()) << p.error().message();
  ASSERT_TRUE((*p)->tracks_grasps());
  auto heads = heads::HeadEvaluator::create(m.metadata());
  ASSERT_TRUE(heads.ok());
  const size_t mini_head = heads->grasp_head_for("gelsight-mini");
  EXPECT_NE(mini_head, 0u) << "the shipped model has a grasp head fitted on GelSight Mini grasps";
  EXPECT_EQ((*p)->grasp_head(), mini_head);
  {
    // Fingers of two models (or of a model without its own head) use the any-sensor head.
    const SensorSetup mixed[2] = {{"A", w, h, 3, 0, "gelsight-mini"}, {"B", w, h, 3, 1, "digit"}};
    auto q = FrameProcessor::create(m, **exec, mixed, po);
    ASSERT_TRUE(q.ok()) << q.error().message();
    EXPECT_EQ((*q)->grasp_head(), 0u);
  }
  uint64_t seq = 0;
  int64_t t = 0;
  int computed = 0;
  for (int64_t i = 0; i < (*gen)->size(); ++i) {
    ASSERT_TRUE((*gen)->generate(i, ep).ok());
    // The episode as the robot lives it: 10 frames of the open gel (the episode's "before"
    // frames), "closed", 10 frames holding the resting object ("during"), "lifting", 10 frames
    // of the lift ("after").
    const auto feed = [&](int frames, const sim::RgbImage* per_finger[2]) {
      for (int k = 0; k < frames; ++k, t += kPeriod, ++seq) {
        for (int32_t f = 0; f < 2; ++f) {
          FrameTimes times;
          times.capture_ns = t + (f == 1 ? 7 * kMs : 0);
          FramePrediction out;
          ASSERT_TRUE((*p)->process(f, seq, view_of(*per_finger[f]), times, out).ok());
        }
      }
    };
    const sim::RgbImage* before[2] = {&ep.frames[0][0], &ep.frames[1][0]};
    const sim::RgbImage* during[2] = {&ep.frames[0][1], &ep.frames[1][1]};
    const sim::RgbImage* after[2] = {&ep.frames[0][2], &ep.frames[1][2]};
    feed(10, before);
    ASSERT_TRUE((*p)->mark_closed(t));
    feed(10, during);
    ASSERT_TRUE((*p)->mark_lifting(t));
    feed(10, after);
    GraspPrediction g;
    ASSERT_TRUE((*p)->take_grasp(g)) << "episode " << i;
    ASSERT_TRUE(g.computed) << "episode " << i << ": " << g.reason.data();
    ++computed;
    // The same frames through the allocating host path and the grasp head, in layout order.
    std::vector<std::vector<float>> e;
    std::vector<std::span<const float>> features;
    for (const heads::GraspFeature& f : heads->grasp_layout()) {
      if (f.kind == heads::FeatureKind::kEmbedding) {
        e.push_back(embed(m, **check_exec, ep.frames[f.finger][static_cast<int>(f.moment)]));
        continue;
      }
      const InputSpec dn = heads::difference_input_spec(m.metadata().input);
      auto open_gel = image::preprocess(view_of(ep.frames[f.finger][0]), dn);
      auto grip = image::preprocess(view_of(ep.frames[f.finger][1]), dn);
      auto stats =
          heads::GraspDifference::create(m.metadata().input.height, m.metadata().input.width, 3);
      ASSERT_TRUE(open_gel.ok() && grip.ok() && stats.ok());
      e.emplace_back(heads::kDifferenceFeatures);
      ASSERT_TRUE(stats->compute(*open_gel, *grip, e.back()).ok());
    }
    for (const auto& v : e) features.emplace_back(v);
    auto want = heads->grasp_probability(features, mini_head);
    ASSERT_TRUE(want.ok());
    EXPECT_EQ(g.probability, *want) << "episode " << i << " (label " << ep.is_gripping << ")";
  }
  EXPECT_EQ(computed, 6);
}

}  // namespace
}  // namespace tlvlink::pipeline
