// The press heads in the per-frame chain: the shipped int8 encoder with a press head added,
// driven by synthetic presses (an imprint that grows, holds and lifts on a calibrated gel). The
// head must answer on a contact's frames from its fourth on, never before, unsmoothed, with
// exactly the head's arithmetic on the peak and first frame computed here from the embeddings
// the processor reported (the offline definition: tools/eval/press_sequence.py); a new contact
// starts from its own first frame.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "support/random.h"
#include "tlvlink/executor.h"
#include "tlvlink/heads/head_math.h"
#include "tlvlink/model.h"
#include "tlvlink/pipeline/frame_processor.h"
#include "tlvlink/quantize/model_copy.h"

namespace tlvlink::pipeline {
namespace {

constexpr int32_t kW = 320, kH = 240;  // a GelSight Mini's processed view

std::vector<uint8_t> gel(testing::Rng& rng, int radius, float depth_dn) {
  std::vector<uint8_t> px(static_cast<size_t>(kW * kH * 3));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const int d2 = (x - 160) * (x - 160) + (y - 120) * (y - 120);
      const float imprint = d2 < radius * radius ? depth_dn : 0.0f;
      for (int c = 0; c < 3; ++c) {
        const float v = 90.0f + 0.2f * static_cast<float>(x) + 25.0f * static_cast<float>(c) +
                        imprint * static_cast<float>(c + 1) / 2.0f + rng.normal(0, 1.5f);
        px[static_cast<size_t>((y * kW + x) * 3 + c)] =
            static_cast<uint8_t>(std::clamp(v, 0.0f, 255.0f));
      }
    }
  return px;
}

struct Seen {
  std::vector<float> embedding;
  float score = 0;
  bool contact = false;
  bool press_answered = false;
  float p_first_label = 0;
};

TEST(PipelinePressReplay, ThePressHeadReadsTheContactsPeakAndFirstFrame) {
  auto shipped = Model::load_file(TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm");
  ASSERT_TRUE(shipped.ok()) << shipped.error().message();
  const int32_t dim = (*shipped)->metadata().embedding_dim;
  // A press head with fixed weights (its values do not matter, its arithmetic does).
  quantize::MetadataSpec meta = quantize::metadata_spec_from((*shipped)->metadata());
  meta.press_heads.erase(meta.press_heads.begin(), meta.press_heads.end());
  quantize::LinearHeadSpec head{"test_press", {"a", "b"}, {}, {0.1f, -0.1f}};
  head.features = std::string(kPressFeatures);
  for (int32_t k = 0; k < 2 * 2 * dim; ++k) head.weight.push_back(std::sin(0.37f * k) * 0.2f);
  meta.press_heads.push_back(head);
  auto builder = quantize::rebuild_with_metadata(**shipped, meta);
  ASSERT_TRUE(builder.ok()) << builder.error().message();
  auto model = Model::load(builder->finish());
  ASSERT_TRUE(model.ok()) << model.error().message();
  const Model& m = **model;
  auto exec = make_executor(m, ExecutorKind::kXnnpack, {.expose_all_tensors = true});
  ASSERT_TRUE(exec.ok()) << exec.error().message();
  ProcessorOptions po;
  po.heads = {"test_press"};
  po.report_embedding = true;
  const SensorSetup sensor{"left", kW, kH, 3, -1, "gelsight-mini"};
  auto proc = FrameProcessor::create(m, **exec, std::span<const SensorSetup>(&sensor, 1), po);
  ASSERT_TRUE(proc.ok()) << proc.error().message();

  testing::Rng rng(7);
  uint64_t seq = 0;
  FramePrediction out;
  const auto play = [&](int radius, float depth) -> Seen {
    const std::vector<uint8_t> px = gel(rng, radius, depth);
    FrameTimes t;
    t.capture_ns = static_cast<int64_t>(seq) * 40'000'000;
    EXPECT_TRUE((*proc)->process(0, seq++, {px.data(), kW, kH, 3, 0}, t, out).ok());
    Seen s;
    s.score = out.contact_score_dn;
    s.contact = out.contact_state == 2;
    if (s.contact)
      s.embedding.assign(out.embedding.begin(), out.embedding.begin() + out.embedding_dim);
    s.press_answered = out.head_count == 1;
    if (s.press_answered) s.p_first_label = out.heads[0].probability[0];
    return s;
  };
  for (int j = 0; j < 30; ++j) play(0, 0);  // the gate's reference
  for (int press = 0; press < 2; ++press) {
    std::vector<Seen> contact;
    const int radii[] = {20, 35, 50, 60, 70, 75, 75, 70, 60, 45};
    for (int r : radii) {
      Seen s = play(r + 10 * press, 40.0f + 10.0f * static_cast<float>(press));
      ASSERT_FALSE(s.embedding.empty()) << "the gate must see the imprint";
      contact.push_back(std::move(s));
    }
    for (size_t j = 0; j < contact.size(); ++j) {
      EXPECT_EQ(contact[j].press_answered, j + 1 >= 4) << "press " << press << " frame " << j;
      if (!contact[j].press_answered) continue;
      // The reference: peak = mean of frames [k-2, k+2] within [0, j], k the first best score.
      size_t k = 0;
      for (size_t i = 1; i <= j; ++i)
        if (contact[i].score > contact[k].score) k = i;
      const size_t lo = k >= 2 ? k - 2 : 0, hi = std::min(j + 1, k + 3);
      std::vector<float> features(static_cast<size_t>(2 * dim));
      for (size_t d = 0; d < static_cast<size_t>(dim); ++d) {
        double sum = 0;
        for (size_t i = lo; i < hi; ++i) sum += static_cast<double>(contact[i].embedding[d]);
        const auto peak = static_cast<float>(sum / static_cast<double>(hi - lo));
        features[d] = peak;
        features[static_cast<size_t>(dim) + d] = peak - contact[0].embedding[d];
      }
      float logits[2], p[2];
      heads::linear_logits(head.weight, head.bias, features, logits);
      heads::softmax(logits, p);
      // The same float operations on the same values: exact but for the peak's summation order.
      EXPECT_NEAR(contact[j].p_first_label, p[0], 1e-5) << "press " << press << " frame " << j;
    }
    // The gate releases after a couple of open frames (hysteresis): until then the contact, and
    // the head's answer over it, go on; after it, no answer.
    for (int j = 0; j < 8; ++j) {
      const Seen s = play(0, 0);
      EXPECT_EQ(s.press_answered, s.contact) << "open frame " << j;
      if (j >= 4) {
        EXPECT_FALSE(s.contact) << "the gate must release";
      }
    }
  }
}

}  // namespace
}  // namespace tlvlink::pipeline
