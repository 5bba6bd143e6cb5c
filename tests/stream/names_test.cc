// Output names: the grasp head a board announces is the one its fingers use (issue 29: a grasp
// head per sensor model), with that head's trust record.
#include "tlvlink/stream/names.h"

#include <cmath>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/test_models.h"

namespace tlvlink::stream {
namespace {

quantize::HeadTrustSpec trust(float accuracy) {
  quantize::HeadTrustSpec t;
  t.present = true;
  t.accuracy = accuracy;
  t.majority = 0.5f;
  t.n = 400;
  t.test_set = "grasp: set (feel_repacked) test split (recorded): 400 items";
  return t;
}

TEST(OutputNames, TheGraspHeadAnnouncedIsTheOneUsedWithItsTrust) {
  testing::TinyInt8Model m;
  m.tweak = [](quantize::ModelBuilder& b) {
    auto& md = b.metadata();
    md.has_grasp_head = true;
    md.grasp_head = {"grasp", "finger0.before,finger0.during", {1, 2, 3, 4}, 0.25f, trust(0.7f)};
    quantize::GraspHeadSpec digit = md.grasp_head;
    digit.trust = trust(0.75f);
    digit.sensors = {"digit"};
    md.sensor_grasp_heads.push_back(digit);
  };
  auto model = testing::load_model(m.build());
  ASSERT_NE(model, nullptr);
  auto heads = heads::HeadEvaluator::create(model->metadata());
  ASSERT_TRUE(heads.ok()) << heads.error().message();
  const OutputNames any = output_names({"A", "B"}, *heads);
  EXPECT_EQ(any.grasp_head, "grasp");
  EXPECT_FLOAT_EQ(any.grasp.accuracy, 0.7f);
  const OutputNames digit = output_names({"A", "B"}, *heads, heads->grasp_head_for("digit"));
  EXPECT_EQ(digit.grasp_head, "grasp");
  EXPECT_FLOAT_EQ(digit.grasp.accuracy, 0.75f);
  EXPECT_FLOAT_EQ(digit.grasp.majority, 0.5f);
}

}  // namespace
}  // namespace tlvlink::stream
