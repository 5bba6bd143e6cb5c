// beta and learning-rate schedules, the architectures' cost, option validation, data order.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "augment.h"
#include "options_json.h"
#include "tlvlink/trainer/arch.h"
#include "tlvlink/trainer/schedule.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer {
namespace {

constexpr double kExact = 1e-12;  // closed-form double arithmetic, a few ulps at most

TEST(BetaSchedule, LinearFollowsThePaper) {
  BetaOptions o;               // linear, beta1 0.9, span 0.9, beta_min 0
  const int64_t total = 1000;  // span = 900 steps
  EXPECT_NEAR(beta_at(o, 0, total), 0.9, kExact);
  EXPECT_NEAR(beta_at(o, 450, total), 0.45, kExact);
  EXPECT_NEAR(beta_at(o, 225, total), 0.675, kExact);
  EXPECT_NEAR(beta_at(o, 900, total), 0.0, kExact);
  EXPECT_NEAR(beta_at(o, 999, total), 0.0, kExact);
}

TEST(BetaSchedule, CosineAndExponentialHitTheEndpoints) {
  BetaOptions o;
  o.beta_min = 0.1;
  const int64_t total = 100;  // span = 90 steps
  o.schedule = BetaSchedule::kCosine;
  EXPECT_NEAR(beta_at(o, 0, total), 0.9, kExact);
  EXPECT_NEAR(beta_at(o, 45, total), 0.5, kExact);  // midpoint of a cosine half-wave
  EXPECT_NEAR(beta_at(o, 90, total), 0.1, kExact);
  EXPECT_NEAR(beta_at(o, 30, total), 0.1 + 0.8 * 0.5 * (1 + std::cos(std::numbers::pi / 3)),
              kExact);  // t = 1/3
  o.schedule = BetaSchedule::kExponential;
  EXPECT_NEAR(beta_at(o, 0, total), 0.9, kExact);
  EXPECT_NEAR(beta_at(o, 90, total), 0.1, kExact);
  // Faster than linear early on: below the linear value at t = 1/3.
  const double e = beta_at(o, 30, total);
  EXPECT_LT(e, 0.9 - 0.8 / 3.0);
  const double k = kExponentialBetaRate;
  EXPECT_NEAR(e, 0.1 + 0.8 * (std::exp(-k / 3) - std::exp(-k)) / (1 - std::exp(-k)), kExact);
  for (BetaSchedule s :
       {BetaSchedule::kLinear, BetaSchedule::kCosine, BetaSchedule::kExponential}) {
    o.schedule = s;
    for (int64_t step = 1; step < total; ++step) {
      EXPECT_LE(beta_at(o, step, total), beta_at(o, step - 1, total)) << beta_schedule_name(s);
    }
  }
}

TEST(BetaSchedule, NoCurriculumIsZeroEverywhere) {
  BetaOptions o;
  o.schedule = BetaSchedule::kNone;
  for (int64_t step : {0, 1, 50, 99}) EXPECT_EQ(beta_at(o, step, 100), 0.0);
}

TEST(BetaSchedule, ParseAndValidate) {
  EXPECT_EQ(parse_beta_schedule("cosine").value(), BetaSchedule::kCosine);
  EXPECT_FALSE(parse_beta_schedule("sigmoid").ok());
  BetaOptions o;
  o.beta_min = 0.95;  // above beta1
  EXPECT_EQ(validate(o).error().code(), ErrorCode::kInvalidArgument);
  o = {};
  o.span = 0;
  EXPECT_FALSE(validate(o).ok());
  o = {};
  o.beta1 = 1.5;
  EXPECT_FALSE(validate(o).ok());
}

TEST(LrSchedule, WarmupThenCosine) {
  LrOptions o;                 // 2e-4, 200 warm-up steps, min 0
  const int64_t total = 1201;  // decay over steps 200..1200
  EXPECT_NEAR(lr_at(o, 0, total), 2e-4 / 200, kExact);
  EXPECT_NEAR(lr_at(o, 99, total), 2e-4 * 100 / 200, kExact);
  EXPECT_NEAR(lr_at(o, 199, total), 2e-4, kExact);
  EXPECT_NEAR(lr_at(o, 200, total), 2e-4, kExact);
  EXPECT_NEAR(lr_at(o, 700, total), 1e-4, kExact);  // halfway through the decay
  EXPECT_NEAR(lr_at(o, 1200, total), 0.0, kExact);
  // Runs shorter than the warm-up warm up over a tenth of the steps instead.
  EXPECT_EQ(effective_warmup(o, 50), 5);
  EXPECT_NEAR(lr_at(o, 4, 50), 2e-4, kExact);
}

TEST(Arch, CostsWithinTheBrief) {
  auto small = make_arch("small", 96, 128, 128);
  auto tiny = make_arch("tiny", 96, 128, 128);
  ASSERT_TRUE(small.ok() && tiny.ok());
  const ArchStats s = arch_stats(*small), t = arch_stats(*tiny);
  // small <= ~60 MMAC, tiny ~10-20 MMAC, a few M parameters at most.
  EXPECT_GT(s.macs, 30'000'000u);
  EXPECT_LT(s.macs, 60'000'000u);
  EXPECT_GT(t.macs, 10'000'000u);
  EXPECT_LT(t.macs, 20'000'000u);
  EXPECT_LT(s.params, 3'000'000u);
  EXPECT_LT(t.params, s.params);
  EXPECT_EQ(s.final_height, 3);
  EXPECT_EQ(s.final_width, 4);
  // Hand count of small's stem: 48x64 outputs x 16 channels x 27 weights.
  EXPECT_EQ(small->layers[0].out_channels, 16);
  for (const LayerSpec& l : small->layers) EXPECT_TRUE(l.kernel == 3 || l.kernel == 1);
  std::printf("%s\n%s\n", describe_arch(*small).c_str(), describe_arch(*tiny).c_str());
}

TEST(Arch, FullResolutionAndLargerFamilies) {
  // tiny-hr takes the 240x320 frame unresized within the daemon budget (README "Architectures");
  // large and large-hr are the bigger supervised references, not edge students.
  auto hr = make_arch("tiny-hr", 240, 320, 128);
  auto large_hr = make_arch("large-hr", 240, 320, 128);
  auto large = make_arch("large", 96, 128, 128);
  ASSERT_TRUE(hr.ok() && large_hr.ok() && large.ok());
  const ArchStats h = arch_stats(*hr), lh = arch_stats(*large_hr), l = arch_stats(*large);
  EXPECT_GT(h.macs, 30'000'000u);
  EXPECT_LT(h.macs, 40'000'000u);
  EXPECT_EQ(h.final_height, 4);  // six stride-2 stages: 240 -> 4, 320 -> 5
  EXPECT_EQ(h.final_width, 5);
  EXPECT_EQ(hr->layers[0].out_channels, 8);
  EXPECT_GT(lh.macs, 5 * h.macs);
  EXPECT_GT(lh.params, 5 * h.params);
  EXPECT_GT(l.macs, 100'000'000u);
  EXPECT_NE(arch_names().find("tiny-hr"), std::string::npos);
}

TEST(Arch, RejectsBadRequests) {
  EXPECT_EQ(make_arch("huge", 96, 128, 128).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(make_arch("small", 16, 128, 128).ok());
  EXPECT_FALSE(make_arch("small", 96, 128, 4).ok());
  EXPECT_EQ(conv_output_size(96, 3, 2), 48);
  EXPECT_EQ(conv_output_size(3, 3, 2), 2);
  EXPECT_EQ(conv_output_size(7, 1, 1), 7);
}

TEST(Options, ValidationNamesTheSetting) {
  TrainOptions o;
  o.data_dir = "/tmp/x";
  o.output = "/tmp/x.ckpt";
  EXPECT_TRUE(validate(o).ok());
  TrainOptions bad = o;
  bad.batch = 1;
  EXPECT_NE(std::string(validate(bad).error().message()).find("batch"), std::string::npos);
  bad = o;
  bad.arch = "resnet50";
  EXPECT_NE(std::string(validate(bad).error().message()).find("resnet50"), std::string::npos);
  bad = o;
  bad.output.clear();
  EXPECT_FALSE(validate(bad).ok());
  bad = o;
  bad.init_temperature = 0.001;  // 1/T = 1000 > max logit scale 100
  EXPECT_FALSE(validate(bad).ok());
}

TEST(Options, ObjectiveAndAugmentation) {
  TrainOptions o;
  o.data_dir = "/tmp/x";
  o.output = "/tmp/x.ckpt";
  o.objective = Objective::kSupervised;
  EXPECT_FALSE(validate(o).ok()) << "supervised with a curriculum";
  o.beta.schedule = BetaSchedule::kNone;
  EXPECT_TRUE(validate(o).ok());
  o.objective = Objective::kTlvLinkSupervised;
  o.supervised_weight = 0;
  EXPECT_NE(std::string(validate(o).error().message()).find("supervised weight"),
            std::string::npos);
  o.supervised_weight = 1;
  o.augment.noise_dn = 60;
  EXPECT_NE(std::string(validate(o).error().message()).find("augmentation"), std::string::npos);
  for (Objective obj : {Objective::kTlvLink, Objective::kSupervised, Objective::kTlvLinkSupervised})
    EXPECT_EQ(parse_objective(objective_name(obj)).value(), obj);
  EXPECT_FALSE(parse_objective("contrastive").ok());
  // The sensor-view options: consistency needs views, prediction consistency needs two views
  // and supervised heads; frames have even sides at least the model input.
  o.augment = {};
  o.view.consistency_weight = 1;
  EXPECT_NE(std::string(validate(o).error().message()).find("needs the view augmentation"),
            std::string::npos);
  o.view.components = kViewAll;
  EXPECT_TRUE(validate(o).ok()) << validate(o).error().message();
  o.view.prediction_weight = 2;
  EXPECT_TRUE(validate(o).ok());
  o.objective = Objective::kTlvLink;
  EXPECT_NE(std::string(validate(o).error().message()).find("supervised heads"), std::string::npos);
  o.objective = Objective::kTlvLinkSupervised;
  o.view.consistency_weight = 0;
  EXPECT_NE(std::string(validate(o).error().message()).find("two views"), std::string::npos);
  o.view.consistency_weight = 1;
  o.view.codec_pairs = 1.5;
  EXPECT_NE(std::string(validate(o).error().message()).find("codec pairs 1.5 outside"),
            std::string::npos);
  o.view.codec_pairs = 0.5;
  EXPECT_TRUE(validate(o).ok());
  o.view.components = kViewAll & ~kViewCodec;
  EXPECT_NE(std::string(validate(o).error().message()).find("the codec view"), std::string::npos);
  o.view.components = kViewAll;
  o.view.codec_pairs = 0;
  o.view.frame_height = 95;
  EXPECT_NE(std::string(validate(o).error().message()).find("view frame"), std::string::npos);
  o.view.frame_height = 240;
  o.resize = ResizeFilter::kNearest;
  EXPECT_NE(std::string(validate(o).error().message()).find("resize filter nearest"),
            std::string::npos);
}

TEST(Options, RoundTripThroughJson) {
  TrainOptions o;
  o.objective = Objective::kTlvLinkSupervised;
  o.supervised_weight = 0.25;
  o.augment = {0.1, 0.05, 3};
  o.arch = "tiny";
  o.beta.schedule = BetaSchedule::kExponential;
  o.beta.beta1 = 0.7;
  o.lr.lr = 3e-4;
  o.seed = 42;
  TrainOptions back;
  ASSERT_TRUE(options_from_json(options_to_json(o), back).ok());
  EXPECT_EQ(back.arch, "tiny");
  EXPECT_EQ(back.beta.schedule, BetaSchedule::kExponential);
  EXPECT_EQ(back.beta.beta1, 0.7);
  EXPECT_EQ(back.lr.lr, 3e-4);
  EXPECT_EQ(back.seed, 42u);
  EXPECT_EQ(back.objective, Objective::kTlvLinkSupervised);
  EXPECT_EQ(back.supervised_weight, 0.25);
  EXPECT_EQ(back.augment.gain_sigma, 0.1);
  EXPECT_EQ(back.augment.noise_dn, 3);
  EXPECT_EQ(back.resize, ResizeFilter::kBilinear);
  EXPECT_FALSE(back.view.enabled());
  o.resize = ResizeFilter::kArea;
  o.view.components = kViewCodec | kViewBlur;
  o.view.consistency_weight = 4;
  o.view.prediction_weight = 2;
  ASSERT_TRUE(options_from_json(options_to_json(o), back).ok());
  EXPECT_EQ(back.resize, ResizeFilter::kArea);
  EXPECT_EQ(back.view.components, kViewCodec | kViewBlur);
  EXPECT_EQ(back.view.consistency_weight, 4);
  EXPECT_EQ(back.view.prediction_weight, 2);
  EXPECT_EQ(back.view.codec_pairs, 0);
  // Written only when used, so the records of earlier runs keep their bytes.
  EXPECT_FALSE(options_to_json(o).at("view").contains("codec_pairs"));
  o.view.codec_pairs = 0.25;
  ASSERT_TRUE(options_from_json(options_to_json(o), back).ok());
  EXPECT_EQ(back.view.codec_pairs, 0.25);
  o.view.codec_pairs = 0;
  // A checkpoint written before the objective existed trained TLV-Link without augmentation.
  nlohmann::ordered_json old = options_to_json(o);
  old.erase("objective");
  old.erase("supervised_weight");
  old.erase("augment");
  old.erase("view");
  old["resize"] = "bilinear";
  ASSERT_TRUE(options_from_json(old, back).ok());
  EXPECT_EQ(back.objective, Objective::kTlvLink);
  EXPECT_FALSE(back.augment.enabled());
  EXPECT_FALSE(back.view.enabled());
  EXPECT_EQ(back.resize, ResizeFilter::kBilinear);
}

TEST(Augment, SeededCameraLikeFrames) {
  std::vector<uint8_t> frame(8 * 8 * 3);
  for (size_t i = 0; i < frame.size(); ++i) frame[i] = static_cast<uint8_t>(40 + (i * 7) % 150);
  std::vector<uint8_t> a(frame.size()), b(frame.size()), c(frame.size());
  const AugmentOptions o{0.1, 0.05, 3};
  augment_frame(frame.data(), a.data(), 8, 8, o, augment_seed(1, 10, 3));
  augment_frame(frame.data(), b.data(), 8, 8, o, augment_seed(1, 10, 3));
  augment_frame(frame.data(), c.data(), 8, 8, o, augment_seed(1, 11, 3));
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_NE(a, frame);
  augment_frame(frame.data(), a.data(), 8, 8, {}, 7);
  EXPECT_EQ(a, frame) << "disabled augmentation copies";
}

TEST(DataOrder, SeededPermutations) {
  const auto a = epoch_order(100, 1, 0), b = epoch_order(100, 1, 0), c = epoch_order(100, 1, 1);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  auto sorted = a;
  std::sort(sorted.begin(), sorted.end());
  for (int64_t i = 0; i < 100; ++i) EXPECT_EQ(sorted[static_cast<size_t>(i)], i);
}

}  // namespace
}  // namespace tlvlink::trainer
