// Reference executor behaviour: inputs/outputs/tensors, NaN/Inf rejection naming the tensor,
// errors naming the operator, the shared executor.h functions, and the every-op graph.
#include <cmath>
#include <limits>
#include <string>

#include "reference/all_ops_models.h"
#include "reference/ref_util.h"

namespace tlvlink::reference_test {
namespace {

// The int8 chain quantizes a [-1, 1] input at 1/20 steps through 12 ops; its sigmoid outputs
// stay within a few output steps (1/256) of fp32. 0.05 is ~13 steps: catches a broken op.
constexpr double kInt8ChainTolerance = 0.05;

bool mentions(const Error& e, const std::string& text) {
  return std::string(e.message()).find(text) != std::string::npos;
}

std::unique_ptr<Executor> make(const Model& model, const ExecutorOptions& options = {}) {
  auto exec = make_reference_executor(model, options);
  EXPECT_TRUE(exec.ok()) << exec.error().message();
  return exec.ok() ? std::move(exec).value() : nullptr;
}

std::vector<float> ramp(size_t n) {
  std::vector<float> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = std::sin(0.37f * static_cast<float>(i));
  return v;
}

TEST(ReferenceExecutor, AllOpsFloatAndInt8AgreeAndStayFinite) {
  auto f = testing::load_model(all_ops_model(false));
  auto q = testing::load_model(all_ops_model(true));
  ASSERT_NE(f, nullptr);
  ASSERT_NE(q, nullptr);
  const std::vector<float> x = ramp(kAllOpsInputElements);
  const auto yf = run1<float>(all_ops_model(false), x);
  const auto yq = run1<float>(all_ops_model(true), x);
  ASSERT_EQ(yf.size(), kAllOpsOutputElements);
  ASSERT_EQ(yq.size(), kAllOpsOutputElements);
  for (size_t i = 0; i < yf.size(); ++i) {
    EXPECT_TRUE(std::isfinite(yf[i]));
    EXPECT_NEAR(yq[i], yf[i], kInt8ChainTolerance) << "output " << i;
  }
  std::printf("[ figures ] all-ops chain outputs: fp32");
  for (float v : yf) std::printf(" %.4f", static_cast<double>(v));
  std::printf(", int8");
  for (float v : yq) std::printf(" %.4f", static_cast<double>(v));
  std::printf("\n");
}

TEST(ReferenceExecutor, BuffersAndTensorAccess) {
  auto model = testing::load_model(all_ops_model(false));
  ASSERT_NE(model, nullptr);
  auto exec = make(*model);
  ASSERT_NE(exec, nullptr);
  EXPECT_EQ(exec->kind(), ExecutorKind::kReference);
  const Graph& g = model->graph();
  EXPECT_EQ(exec->input(0).size(), g.tensor(g.inputs[0]).bytes());
  EXPECT_EQ(reinterpret_cast<uintptr_t>(exec->input(0).data()) % 16, 0u);
  EXPECT_TRUE(exec->input(1).empty());
  EXPECT_TRUE(exec->output(1).empty());
  const std::vector<float> x = ramp(kAllOpsInputElements);
  std::memcpy(exec->input(0).data(), x.data(), exec->input(0).size());
  ASSERT_TRUE(exec->invoke().ok());
  const auto first = from_bytes<float>(exec->output(0));
  ASSERT_TRUE(exec->invoke().ok());  // repeatable: same inputs, same outputs
  EXPECT_EQ(from_bytes<float>(exec->output(0)), first);

  // Every tensor is readable: constants (their model data), and every activation even without
  // expose_all_tensors (the reference executor keeps them all).
  for (size_t t = 0; t < g.tensors.size(); ++t) {
    auto data = exec->tensor(static_cast<int32_t>(t));
    ASSERT_TRUE(data.ok()) << data.error().message();
    EXPECT_EQ(data->size(), g.tensors[t].bytes()) << g.tensors[t].name;
    if (g.tensors[t].is_constant()) {
      EXPECT_EQ(data->data(), g.tensors[t].data.data());
    }
  }
  auto out = exec->tensor(g.outputs[0]);
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(out->data(), exec->output(0).data());
  auto bad = exec->tensor(static_cast<int32_t>(g.tensors.size()));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(exec->tensor(-1).ok());
}

TEST(ReferenceExecutor, NonFiniteInputRejectedWithItsName) {
  auto model = testing::load_model(all_ops_model(true));
  ASSERT_NE(model, nullptr);
  auto exec = make(*model);
  ASSERT_NE(exec, nullptr);
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    std::vector<float> x = ramp(kAllOpsInputElements);
    x[37] = bad;
    std::memcpy(exec->input(0).data(), x.data(), exec->input(0).size());
    const Status s = exec->invoke();
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code(), ErrorCode::kNonFiniteValue);
    EXPECT_TRUE(mentions(s.error(), "input") && mentions(s.error(), "frame"))
        << s.error().message();
    EXPECT_TRUE(mentions(s.error(), "element 37")) << s.error().message();
    std::printf("[ message ] %s\n", s.error().message());
  }
}

TEST(ReferenceExecutor, NonFiniteOutputRejectedUnlessChecksAreOff) {
  // 3e38 * 10 overflows float32 to +inf in the FC output.
  ModelBuilder m;
  const int32_t x = m.add_activation("x", DType::kFloat32, {1, 2});
  const std::vector<float> w{10, 0};
  const int32_t wt = m.add_constant<float>("w", {1, 2}, std::span<const float>(w));
  const int32_t y = m.add_activation("logits", DType::kFloat32, {1, 1});
  m.add_op(OpType::kFullyConnected, "fc", {x, wt, kNoTensor}, y, FullyConnectedParams{});
  m.set_inputs({x});
  m.set_outputs({y});
  auto model = testing::load_model(m.finish());
  ASSERT_NE(model, nullptr);
  const std::vector<float> big{3e38f, 1};
  for (bool check : {true, false}) {
    ExecutorOptions options;
    options.check_outputs = check;
    auto exec = make(*model, options);
    ASSERT_NE(exec, nullptr);
    std::memcpy(exec->input(0).data(), big.data(), 8);
    // invoke() refuses 3e38 up front (beyond float_input_limit: 3e38 x 10 overflows); the
    // output check is what remains when the input scan is skipped.
    const Status early = exec->invoke();
    ASSERT_FALSE(early.ok());
    EXPECT_TRUE(mentions(early.error(), "input") && mentions(early.error(), "overflow"))
        << early.error().message();
    const Status s = exec->invoke_trusted_inputs();
    if (check) {
      ASSERT_FALSE(s.ok());
      EXPECT_EQ(s.error().code(), ErrorCode::kNonFiniteValue);
      EXPECT_TRUE(mentions(s.error(), "output") && mentions(s.error(), "logits"))
          << s.error().message();
    } else {
      EXPECT_TRUE(s.ok()) << s.error().message();
      EXPECT_TRUE(std::isinf(from_bytes<float>(exec->output(0))[0]));
    }
  }
}

TEST(ReferenceExecutor, AsymmetricInt8WeightsRejectedAtLoadNamingTheOperator) {
  // XNNPACK's int8 weights are symmetric, so the loader refuses a weight zero point instead of
  // letting one executor honour it and the other ignore it.
  ModelBuilder m;
  const int32_t x = m.add_activation("x", DType::kInt8, {1, 2}, QuantSpec::per_tensor(0.1f, 0));
  const std::vector<int8_t> w{1, 2};
  const int32_t wt = m.add_constant<int8_t>("w", {1, 2}, std::span<const int8_t>(w),
                                            QuantSpec::per_tensor(0.1f, 5));
  const int32_t y = m.add_activation("y", DType::kInt8, {1, 1}, QuantSpec::per_tensor(0.1f, 0));
  m.add_op(OpType::kFullyConnected, "head", {x, wt, kNoTensor}, y, FullyConnectedParams{});
  m.set_inputs({x});
  m.set_outputs({y});
  const Error e = testing::load_error(m.finish());
  EXPECT_EQ(e.code(), ErrorCode::kModelInvalidOperator);
  EXPECT_TRUE(mentions(e, "operator 0 FullyConnected 'head'")) << e.message();
  EXPECT_TRUE(mentions(e, "zero_point[0] = 5")) << e.message();
}

TEST(ExecutorCommon, KindNamesParseAndDispatch) {
  EXPECT_STREQ(executor_kind_name(ExecutorKind::kReference), "reference");
  EXPECT_STREQ(executor_kind_name(ExecutorKind::kXnnpack), "xnnpack");
  auto r = parse_executor_kind("reference");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, ExecutorKind::kReference);
  auto x = parse_executor_kind("xnnpack");
  ASSERT_TRUE(x.ok());
  EXPECT_EQ(*x, ExecutorKind::kXnnpack);
  auto bad = parse_executor_kind("tflite");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_TRUE(mentions(bad.error(), "'tflite'")) << bad.error().message();

  auto model = testing::load_model(all_ops_model(false));
  ASSERT_NE(model, nullptr);
  auto ref = make_executor(*model, ExecutorKind::kReference);
  ASSERT_TRUE(ref.ok()) << ref.error().message();
  EXPECT_EQ((*ref)->kind(), ExecutorKind::kReference);
#if !defined(TLVLINK_HAVE_XNNPACK)
  auto xnn = make_executor(*model, ExecutorKind::kXnnpack);
  ASSERT_FALSE(xnn.ok());
  EXPECT_EQ(xnn.error().code(), ErrorCode::kModelUnsupported);
  EXPECT_TRUE(mentions(xnn.error(), "TLVLINK_WITH_XNNPACK=OFF")) << xnn.error().message();
#endif
}

TEST(ExecutorCommon, CheckFiniteNamesWhatIndexAndValue) {
  const std::vector<float> ok{0, -1, 3e38f};
  EXPECT_TRUE(check_finite(ok, "x").ok());
  EXPECT_TRUE(check_finite({}, "empty").ok());
  const std::vector<float> bad{0, 1, std::numeric_limits<float>::infinity(), NAN};
  const Status s = check_finite(bad, "embedding");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kNonFiniteValue);
  EXPECT_TRUE(mentions(s.error(), "embedding") && mentions(s.error(), "element 2") &&
              mentions(s.error(), "inf"))
      << s.error().message();
}

}  // namespace
}  // namespace tlvlink::reference_test
