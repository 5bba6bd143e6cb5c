// `tlvlink adapt`'s comparison in-process: a small trained encoder, exported, compared with its
// adapted last layer on a labelled folder; the linear side is exactly what `heads fit --images`
// records; a checkpoint that is not the model's, or bad options, are errors naming them.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "support/labelled_folder.h"
#include "tlvlink/eval/labelled_frames.h"
#include "tlvlink/eval/user_head.h"
#include "tlvlink/model.h"
#include "tlvlink/trainer/adapt.h"
#include "trainer/trainer_support.h"

namespace tlvlink::trainer {
namespace {

using testing::quick_options;
using testing::TempDir;

class Adapt : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>("adapt");
    ASSERT_TRUE(testing::write_touch_set(*dir_ / "t100k", 8, 6, 21).ok());
    for (const char* name : {"a", "b"}) {
      TrainOptions o = quick_options(*dir_ / "t100k", *dir_ / (std::string(name) + ".ckpt"));
      o.seed = name[0] == 'a' ? 1 : 2;
      auto t = train(o);
      ASSERT_TRUE(t.ok()) << t.error().message();
    }
    ExportOptions e;
    e.checkpoint = *dir_ / "a.ckpt";
    e.output = *dir_ / "a.tlvm";
    ASSERT_TRUE(export_model(e).ok());
    // 3 objects per class, 4 frames each: 3 grouped folds.
    ::tlvlink::testing::write_colour_folder(*dir_ / "frames", 3, 128, 96);
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static std::unique_ptr<TempDir> dir_;
};
std::unique_ptr<TempDir> Adapt::dir_;

TEST_F(Adapt, ComparesOnTheSameFoldsAsHeadsFit) {
  auto model = Model::load_file((*dir_ / "a.tlvm").c_str());
  ASSERT_TRUE(model.ok()) << model.error().message();
  auto frames = eval::read_labelled_folder(*dir_ / "frames");
  ASSERT_TRUE(frames.ok()) << frames.error().message();
  AdaptOptions o;
  o.checkpoint = *dir_ / "a.ckpt";
  o.steps = 20;
  // No step: the classifier is each fold's linear head on the libtorch encoder, so the answers
  // are the linear head's.
  o.steps = 0;
  auto start = compare_adapted_head(**model, *frames, "", o);
  ASSERT_TRUE(start.ok()) << start.error().message();
  EXPECT_EQ(start->adapted_only_right + start->linear_only_right, 0)
      << format_adapt_comparison(*start, "colour");
  o.steps = 20;
  auto c = compare_adapted_head(**model, *frames, "", o);
  ASSERT_TRUE(c.ok()) << c.error().message();
  // The libtorch encoder against the exported graph (kParityCosine in train_export_test).
  EXPECT_GE(c->encoder_cosine, 0.9999);
  EXPECT_EQ(c->n, 24);
  EXPECT_EQ(c->groups, 6);
  EXPECT_EQ(c->classes, 2);
  EXPECT_EQ(c->folds, 3);
  EXPECT_DOUBLE_EQ(c->majority, 0.5);
  // The linear side is the head `heads fit --images` fits and records (same folds, same seed,
  // the reference executor for both): identical figures, not merely close.
  eval::UserHeadOptions uh;
  uh.head = "colour";
  uh.embedder.executor = ExecutorKind::kReference;
  auto fit = eval::fit_user_head(**model, *frames, uh);
  ASSERT_TRUE(fit.ok()) << fit.error().message();
  EXPECT_DOUBLE_EQ(c->linear.accuracy, fit->head_cv.accuracy);
  EXPECT_DOUBLE_EQ(c->linear.ci_low, fit->head_cv.ci_low);
  // What adapting promises: its fitting rows fit better after the steps than at the start
  // (the linear head's solution). Whether it generalises is what the comparison measures.
  EXPECT_LT(c->fit_loss_end, c->fit_loss_start);
  EXPECT_DOUBLE_EQ(start->fit_loss_start, start->fit_loss_end);
  // Paired counts: the difference in right answers, row for row.
  EXPECT_EQ(c->adapted_only_right - c->linear_only_right,
            std::llround((c->adapted.accuracy - c->linear.accuracy) * 24));
  const std::string text = format_adapt_comparison(*c, "colour");
  EXPECT_NE(text.find("verdict: "), std::string::npos) << text;
  EXPECT_NE(text.find("the last 1 conv layer(s) + FC"), std::string::npos) << text;
}

TEST_F(Adapt, RefusesACheckpointThatIsNotTheModelsAndBadOptions) {
  auto model = Model::load_file((*dir_ / "a.tlvm").c_str());
  ASSERT_TRUE(model.ok());
  auto frames = eval::read_labelled_folder(*dir_ / "frames");
  ASSERT_TRUE(frames.ok());
  AdaptOptions o;
  o.steps = 2;
  o.checkpoint = *dir_ / "b.ckpt";  // another seed: another encoder
  const auto message = [&] {
    auto c = compare_adapted_head(**model, *frames, "", o);
    return c.ok() ? std::string("(accepted)") : std::string(c.error().message());
  };
  EXPECT_NE(message().find("does not compute the model's embeddings"), std::string::npos)
      << message();
  o.checkpoint = *dir_ / "missing.ckpt";
  EXPECT_NE(message().find("missing.ckpt"), std::string::npos) << message();
  o.checkpoint = *dir_ / "a.ckpt";
  o.layers = 99;
  EXPECT_NE(message().find("--layers 99"), std::string::npos) << message();
  o.layers = 1;
  o.lr = -1;
  EXPECT_EQ(compare_adapted_head(**model, *frames, "", o).error().code(),
            ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace tlvlink::trainer
