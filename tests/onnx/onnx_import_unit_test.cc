// ONNX import on hand-built ModelProtos (no Python needed): what the importer refuses and why,
// and folding arithmetic checked against values computed here.

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <onnx/onnx_pb.h>

#include "tlvlink/executor.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/onnx_import.h"

namespace tlvlink {
namespace {

using quantize::import_onnx;
using quantize::OnnxImportOptions;

// A folded constant (bias - c, w / d) is rounded once more than the unfused arithmetic.
constexpr float kFoldTolerance = 1e-5f;

class Onnx {
 public:
  explicit Onnx(int64_t opset = 13, std::vector<int64_t> input = {1, 3, 4, 4}) {
    model_.set_ir_version(8);
    model_.set_producer_name("onnx_import_unit_test");
    onnx::OperatorSetIdProto* id = model_.add_opset_import();
    id->set_domain("");
    id->set_version(opset);
    g_ = model_.mutable_graph();
    g_->set_name("unit");
    value(g_->add_input(), "x", input, onnx::TensorProto_DataType_FLOAT);
  }
  onnx::NodeProto* node(const std::string& op, std::vector<std::string> in,
                        std::vector<std::string> out, const std::string& name = "") {
    onnx::NodeProto* n = g_->add_node();
    n->set_op_type(op);
    n->set_name(name.empty() ? op + "_" + std::to_string(g_->node_size()) : name);
    for (const auto& s : in) n->add_input(s);
    for (const auto& s : out) n->add_output(s);
    return n;
  }
  onnx::TensorProto* init(const std::string& name, std::vector<int64_t> dims,
                          std::vector<float> v) {
    onnx::TensorProto* t = g_->add_initializer();
    t->set_name(name);
    t->set_data_type(onnx::TensorProto_DataType_FLOAT);
    for (int64_t d : dims) t->add_dims(d);
    for (float f : v) t->add_float_data(f);
    return t;
  }
  void init_i64(const std::string& name, std::vector<int64_t> v) {
    onnx::TensorProto* t = g_->add_initializer();
    t->set_name(name);
    t->set_data_type(onnx::TensorProto_DataType_INT64);
    t->add_dims(static_cast<int64_t>(v.size()));
    for (int64_t i : v) t->add_int64_data(i);
  }
  void output(const std::string& name) {
    value(g_->add_output(), name, {}, onnx::TensorProto_DataType_FLOAT);
  }
  onnx::GraphProto& graph() { return *g_; }
  onnx::ModelProto& model() { return model_; }

  Result<quantize::OnnxImportResult> convert() const {
    const std::string s = model_.SerializeAsString();
    return import_onnx(std::as_bytes(std::span(s.data(), s.size())), OnnxImportOptions{});
  }
  // Converts, expecting an error whose message contains `part`.
  std::string error_of() const {
    auto r = convert();
    EXPECT_FALSE(r.ok());
    return r.ok() ? "" : r.error().message();
  }

 private:
  static void value(onnx::ValueInfoProto* v, const std::string& name, std::vector<int64_t> dims,
                    int type) {
    v->set_name(name);
    onnx::TypeProto_Tensor* t = v->mutable_type()->mutable_tensor_type();
    t->set_elem_type(type);
    if (dims.empty()) return;
    for (int64_t d : dims) t->mutable_shape()->add_dim()->set_dim_value(d);
  }
  onnx::ModelProto model_;
  onnx::GraphProto* g_;
};

void set_ints(onnx::NodeProto* n, const std::string& name, std::vector<int64_t> v) {
  onnx::AttributeProto* a = n->add_attribute();
  a->set_name(name);
  a->set_type(onnx::AttributeProto_AttributeType_INTS);
  for (int64_t i : v) a->add_ints(i);
}
void set_int(onnx::NodeProto* n, const std::string& name, int64_t v) {
  onnx::AttributeProto* a = n->add_attribute();
  a->set_name(name);
  a->set_type(onnx::AttributeProto_AttributeType_INT);
  a->set_i(v);
}

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

// A 1x1 conv 3 -> 2 channels on x, output "c".
void add_conv(Onnx& o, const std::string& in = "x", const std::string& out = "c") {
  o.init("w", {2, 3, 1, 1}, {1, 2, 3, -1, 0.5f, 0.25f});
  o.init("b", {2}, {0.5f, -1});
  o.node("Conv", {in, "w", "b"}, {out}, "conv");
}

std::vector<float> run_reference(const std::vector<std::byte>& file, std::vector<float> x) {
  auto m = Model::load(file);
  EXPECT_TRUE(m.ok());
  if (!m.ok()) return {};
  auto e = make_reference_executor(**m);
  EXPECT_TRUE(e.ok());
  std::memcpy((*e)->input(0).data(), x.data(), x.size() * sizeof(float));
  EXPECT_TRUE((*e)->invoke().ok());
  const auto out = (*e)->output(0);
  const auto* f = reinterpret_cast<const float*>(out.data());
  return {f, f + out.size() / sizeof(float)};
}

TEST(OnnxUnit, GarbageAndEmptyFilesAreFormatErrors) {
  const std::string garbage = "this is not an onnx file at all";
  auto r = import_onnx(std::as_bytes(std::span(garbage.data(), garbage.size())), {});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kFormat) << r.error().message();
  auto e = import_onnx({}, {});
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().code(), ErrorCode::kFormat);
}

TEST(OnnxUnit, OpsetOutsideTheSupportedRangeIsRejected) {
  for (int64_t opset : {6, 22}) {
    Onnx o(opset);
    o.node("Relu", {"x"}, {"y"});
    o.output("y");
    const std::string e = o.error_of();
    EXPECT_HAS(e, "opset " + std::to_string(opset));
    EXPECT_HAS(e, "7 to 21");
  }
}

TEST(OnnxUnit, InputsMustBeOneFixedSizeFloatFrame) {
  Onnx two;
  two.graph().add_input()->CopyFrom(two.graph().input(0));
  two.graph().mutable_input(1)->set_name("x2");
  two.node("Add", {"x", "x2"}, {"y"});
  two.output("y");
  EXPECT_HAS(two.error_of(), "2 inputs");

  Onnx batch2(13, {2, 3, 4, 4});
  batch2.node("Relu", {"x"}, {"y"});
  batch2.output("y");
  EXPECT_HAS(batch2.error_of(), "batch 2");

  Onnx flat(13, {1, 12});
  flat.node("Relu", {"x"}, {"y"});
  flat.output("y");
  EXPECT_HAS(flat.error_of(), "rank 2");

  Onnx channels(13, {1, 4, 8, 8});
  channels.node("Relu", {"x"}, {"y"});
  channels.output("y");
  EXPECT_HAS(channels.error_of(), "4 channels");
}

TEST(OnnxUnit, GraphStructureErrors) {
  Onnx undefined;
  undefined.node("Relu", {"nowhere"}, {"y"}, "r");
  undefined.output("y");
  EXPECT_HAS(undefined.error_of(), "reads 'nowhere'");

  Onnx domain;
  domain.node("FusedConv", {"x"}, {"y"}, "fc")->set_domain("com.microsoft");
  domain.output("y");
  EXPECT_HAS(domain.error_of(), "domain 'com.microsoft'");

  Onnx transpose;
  set_ints(transpose.node("Transpose", {"x"}, {"y"}, "t"), "perm", {0, 2, 3, 1});
  transpose.output("y");
  const std::string e = transpose.error_of();
  EXPECT_HAS(e, "Transpose node 't'");
  EXPECT_HAS(e, "constants only");
}

TEST(OnnxUnit, InitializerProblemsNameTheInitializer) {
  Onnx inf;
  add_conv(inf);
  inf.graph().mutable_initializer(0)->set_float_data(4, std::numeric_limits<float>::infinity());
  inf.output("c");
  const std::string e = inf.error_of();
  EXPECT_HAS(e, "initializer 'w' value 4 is Inf");

  Onnx half;
  add_conv(half);
  half.graph().mutable_initializer(0)->set_data_type(onnx::TensorProto_DataType_FLOAT16);
  half.output("c");
  EXPECT_HAS(half.error_of(), "initializer 'w' has data type FLOAT16");

  Onnx external;
  add_conv(external);
  external.graph().mutable_initializer(0)->set_data_location(
      onnx::TensorProto_DataLocation_EXTERNAL);
  external.output("c");
  EXPECT_HAS(external.error_of(), "external file");

  Onnx computed;
  computed.node("Relu", {"x"}, {"w"});
  computed.node("Conv", {"x", "w"}, {"c"}, "conv");
  computed.output("c");
  EXPECT_HAS(computed.error_of(), "must be a constant");
}

TEST(OnnxUnit, FlattenedFeatureMapNeedsAConsumerThatAbsorbsThePermutation) {
  Onnx o;
  o.node("Flatten", {"x"}, {"f"}, "flat");
  o.output("f");
  EXPECT_HAS(o.error_of(), "flattened NCHW feature map");
}

TEST(OnnxUnit, MaxPoolCeilModeOnlyWhenItChangesNothing) {
  for (int64_t side : {4, 5}) {
    Onnx o(13, {1, 3, side, side});
    onnx::NodeProto* n = o.node("MaxPool", {"x"}, {"y"}, "pool");
    set_ints(n, "kernel_shape", {2, 2});
    set_ints(n, "strides", {2, 2});
    set_int(n, "ceil_mode", 1);
    o.output("y");
    auto r = o.convert();
    EXPECT_EQ(r.ok(), side == 4) << (r.ok() ? "converted" : r.error().message());
  }
}

TEST(OnnxUnit, RejectedOperandForms) {
  Onnx sub;
  sub.init("k", {1}, {1.0f});
  sub.node("Sub", {"k", "x"}, {"y"}, "s");
  sub.output("y");
  EXPECT_HAS(sub.error_of(), "constant - activation");

  Onnx gemm(13, {1, 3, 1, 1});
  gemm.node("Flatten", {"x"}, {"f"});
  gemm.init("B", {3, 2}, {1, 2, 3, 4, 5, 6});
  set_int(gemm.node("Gemm", {"f", "B"}, {"y"}, "g"), "transA", 1);
  gemm.output("y");
  EXPECT_HAS(gemm.error_of(), "transA=1");
}

TEST(OnnxUnit, IdentityDropoutSubDivFoldIntoTheConv) {
  Onnx o;
  o.node("Identity", {"x"}, {"i"});
  o.node("Dropout", {"i"}, {"d"});
  add_conv(o, "d", "c");
  o.init("shift", {1, 2, 1, 1}, {0.25f, -0.5f});
  o.node("Sub", {"c", "shift"}, {"s"});
  o.init("two", {}, {2.0f});
  o.node("Div", {"s", "two"}, {"y"});
  o.output("y");
  auto r = o.convert();
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->summary.operators, 1u);  // the conv, with Sub and Div folded in
  EXPECT_EQ(r->summary.fused, 2u);
  // x is NHWC [1,4,4,3]; pixel p has channels (p, 2p, 3p) * 0.01.
  std::vector<float> x(48);
  for (size_t i = 0; i < 16; ++i) {
    for (size_t c = 0; c < 3; ++c) x[i * 3 + c] = 0.01f * static_cast<float>(i * (c + 1));
  }
  const std::vector<float> y = run_reference(r->model, x);
  ASSERT_EQ(y.size(), 32u);
  const float w[2][3] = {{1, 2, 3}, {-1, 0.5f, 0.25f}}, b[2] = {0.5f, -1}, sh[2] = {0.25f, -0.5f};
  for (size_t i = 0; i < 16; ++i) {
    for (size_t o2 = 0; o2 < 2; ++o2) {
      float acc = b[o2];
      for (size_t c = 0; c < 3; ++c) acc += w[o2][c] * x[i * 3 + c];
      EXPECT_NEAR(y[i * 2 + o2], (acc - sh[o2]) / 2.0f, kFoldTolerance) << "pixel " << i;
    }
  }
}

TEST(OnnxUnit, ClipsBecomeReluSixWhenTheyCanElseClamp) {
  struct Case {
    float lo, hi;
    bool relu_first;
    size_t operators;
  };
  // Clip(0,6) and Relu+Clip(0,6) fuse; Clip(-1,1) cannot be a fused activation.
  for (const Case& k : {Case{0, 6, false, 1}, Case{0, 6, true, 1}, Case{-1, 1, false, 2}}) {
    Onnx o;
    add_conv(o);
    std::string in = "c";
    if (k.relu_first) {
      o.node("Relu", {"c"}, {"r"});
      in = "r";
    }
    o.init("lo", {}, {k.lo});
    o.init("hi", {}, {k.hi});
    o.node("Clip", {in, "lo", "hi"}, {"y"});
    o.output("y");
    auto r = o.convert();
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(r->summary.operators, k.operators) << k.lo << ".." << k.hi;
  }
}

}  // namespace
}  // namespace tlvlink
