// Executors agree on float inputs extreme enough to overflow float32 inside the graph (issue 12):
// 3e38 once gave a finite embedding on XNNPACK (its fused clamps turn NaN into a bound on x86) and
// a NaN error on the reference. Both now reject an input beyond float_input_limit before running,
// with the same error, and below the limit both give finite outputs that agree.
#include <cfloat>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/executor.h"
#include "tlvlink/model.h"

namespace tlvlink {
namespace {

struct Outcome {
  ErrorCode code = ErrorCode::kOk;
  std::string message;
  bool outputs_finite = true;
};

Outcome run(const Model& model, std::unique_ptr<Executor>& exec, float value, bool alternate) {
  const std::span<std::byte> in = exec->input(0);
  std::vector<float> v(in.size() / sizeof(float), value);
  if (alternate) {
    for (size_t i = 1; i < v.size(); i += 2) v[i] = -value;  // cancellation: Inf - Inf = NaN
  }
  std::memcpy(in.data(), v.data(), in.size());
  Outcome r;
  const Status s = exec->invoke();
  if (!s.ok()) {
    r.code = s.error().code();
    r.message = s.error().message();
    return r;
  }
  const Tensor& out = model.graph().tensor(model.graph().outputs[0]);
  if (out.dtype == DType::kFloat32) {
    const auto* f = reinterpret_cast<const float*>(exec->output(0).data());
    for (size_t i = 0; i < out.shape.elements(); ++i) r.outputs_finite &= std::isfinite(f[i]) != 0;
  }
  return r;
}

class ExtremeInputs : public ::testing::TestWithParam<const char*> {};

TEST_P(ExtremeInputs, BothExecutorsAgree) {
  const std::string path =
      std::string(TLVLINK_SOURCE_DIR) + "/firmware/models/" + GetParam() + ".tlvm";
  auto model = Model::load_file(path.c_str());
  ASSERT_TRUE(model.ok()) << model.error().message();
  const Model& m = **model;
  ASSERT_EQ(m.graph().tensor(m.graph().inputs[0]).dtype, DType::kFloat32);
  const float limit = float_input_limit(m.graph()).limit;
  // A normalised frame is within a few units; the limit must leave ordinary inputs alone.
  EXPECT_GT(limit, 1e6f) << GetParam();
  EXPECT_LT(limit, FLT_MAX) << GetParam() << ": its first convolution can overflow at FLT_MAX";
  auto xnn = make_executor(m, ExecutorKind::kXnnpack);
  auto ref = make_executor(m, ExecutorKind::kReference);
  ASSERT_TRUE(ref.ok()) << ref.error().message();
  // tests/stability is built only with XNNPACK: an executor that cannot be made is a failure.
  ASSERT_TRUE(xnn.ok()) << xnn.error().message();
  for (const float value :
       {3e38f, FLT_MAX, 1e38f, limit * 1.01f, limit * 0.99f, limit / 16, 1e20f, 100.0f}) {
    for (const bool alternate : {false, true}) {
      SCOPED_TRACE(::testing::Message()
                   << GetParam() << " input " << value << (alternate ? " alternating sign" : ""));
      const Outcome a = run(m, *xnn, value, alternate);
      const Outcome b = run(m, *ref, value, alternate);
      EXPECT_EQ(a.code, b.code) << a.message << " | " << b.message;
      EXPECT_EQ(a.message, b.message);  // reported the same way
      if (value > limit) {
        EXPECT_EQ(a.code, ErrorCode::kNonFiniteValue);
        EXPECT_NE(a.message.find("overflow"), std::string::npos) << a.message;
      } else {
        EXPECT_EQ(a.code, ErrorCode::kOk) << a.message;
        EXPECT_EQ(b.code, ErrorCode::kOk) << b.message;
        EXPECT_TRUE(a.outputs_finite && b.outputs_finite);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shipped, ExtremeInputs,
                         ::testing::Values("touch-tiny-fp32", "touch-tiny-int8"));

}  // namespace
}  // namespace tlvlink
