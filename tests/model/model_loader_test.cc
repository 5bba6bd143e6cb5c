// A valid model round-trips through the writer and loader with every field intact.
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/test_models.h"

namespace tlvlink::testing {
namespace {

TEST(ModelLoader, RoundTripsGraph) {
  auto model = load_model(TinyInt8Model().build());
  ASSERT_NE(model, nullptr);
  const Graph& g = model->graph();
  ASSERT_EQ(g.tensors.size(), 10u);
  EXPECT_EQ(g.tensor(2).name, "conv.weight");
  EXPECT_EQ(g.tensor(2).dtype, DType::kInt8);
  EXPECT_EQ(g.tensor(2).shape, (Shape{{4, 3, 3, 3}, 4}));
  EXPECT_EQ(g.tensor(2).quant.axis, 0);
  ASSERT_EQ(g.tensor(2).quant.scale.size(), 4u);
  EXPECT_FLOAT_EQ(g.tensor(2).quant.scale[1], 0.02f);
  EXPECT_TRUE(g.tensor(2).is_constant());
  EXPECT_EQ(reinterpret_cast<uintptr_t>(g.tensor(2).data.data()) % 16, 0u)
      << "constants are 16-byte aligned";
  EXPECT_FALSE(g.tensor(4).is_constant());
  EXPECT_EQ(g.tensor(4).quant.zero_point[0], -10);

  ASSERT_EQ(g.operators.size(), 6u);
  const Operator& conv = g.operators[1];
  EXPECT_EQ(conv.type, OpType::kConv2D);
  EXPECT_EQ(conv.name, "conv");
  EXPECT_EQ(conv.input_count, 3u);
  EXPECT_EQ(conv.output, 4);
  const auto& p = conv.get<Conv2DParams>();
  EXPECT_EQ(p.kernel_h, 3);
  EXPECT_EQ(p.pad_left, 1);
  EXPECT_EQ(p.activation, Activation::kRelu);
  EXPECT_EQ(g.operators[4].inputs[2], kNoTensor) << "FC without bias";
  EXPECT_EQ(g.inputs, std::vector<int32_t>{0});
  EXPECT_EQ(g.outputs, std::vector<int32_t>{9});
}

TEST(ModelLoader, RoundTripsMetadata) {
  TinyInt8Model m;
  m.tweak = [](quantize::ModelBuilder& b) {
    auto& md = b.metadata();
    md.linear_heads.push_back({"hard_soft", {"hard", "soft"}, {1, 2, 3, 4}, {0.5f, -0.5f}});
    md.zero_shot_heads.push_back(
        {"material", {"wood", "metal"}, "This feels like {}.", {1, 0, 0, 1}, 50});
    md.has_grasp_head = true;
    md.grasp_head = {"grasp", "finger0.before,finger0.during", {1, 2, 3, 4}, 0.25f};
    md.training_json = R"({"kind":"test"})";
    md.golden.push_back({std::vector<std::byte>(8 * 8 * 3 * 4, std::byte{0}),
                         std::vector<std::byte>(2 * 4, std::byte{1})});
  };
  auto model = load_model(m.build());
  ASSERT_NE(model, nullptr);
  const Metadata& md = model->metadata();
  EXPECT_EQ(md.name, "tiny");
  EXPECT_EQ(md.embedding_dim, 2);
  ASSERT_EQ(md.linear_heads.size(), 1u);
  EXPECT_EQ(md.linear_heads[0].labels[1], "soft");
  EXPECT_FLOAT_EQ(md.linear_heads[0].bias[1], -0.5f);
  ASSERT_EQ(md.zero_shot_heads.size(), 1u);
  EXPECT_EQ(md.zero_shot_heads[0].prompt_template, "This feels like {}.");
  EXPECT_FLOAT_EQ(md.zero_shot_heads[0].logit_scale, 50);
  EXPECT_TRUE(md.grasp_head.present);
  EXPECT_FLOAT_EQ(md.grasp_head.bias, 0.25f);
  EXPECT_EQ(md.provenance.producer, "tlvlink");
  EXPECT_EQ(md.provenance.training, R"({"kind":"test"})");
  EXPECT_NE(md.provenance.content_checksum, 0u);
  ASSERT_EQ(md.golden.size(), 1u);
  EXPECT_EQ(md.golden[0].output[0], std::byte{1});
}

TEST(ModelLoader, MissingFileIsIoErrorWithPath) {
  auto result = Model::load_file("/nonexistent/dir/model.tlvm");
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code(), ErrorCode::kIo);
  EXPECT_NE(std::string(result.error().message()).find("/nonexistent/dir/model.tlvm"),
            std::string::npos);
}

TEST(ModelLoader, ErrorMessagesAreBoundedWithEllipsis) {
  const std::string long_name(1000, 'x');
  const Error e =
      Error::make(ErrorCode::kModelInvalidTensor, "tensor '%s' is bad", long_name.c_str());
  EXPECT_EQ(std::strlen(e.message()), Error::kMaxErrorMessage);
  EXPECT_EQ(std::string(e.message()).substr(Error::kMaxErrorMessage - 3), "...");
}

}  // namespace
}  // namespace tlvlink::testing
