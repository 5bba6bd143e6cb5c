// Property-style agreement on randomized graphs: random conv geometry (strides, paddings,
// dilations, dense / depthwise / grouped), random calibrated scales and zero points, fused
// activations, broadcasting Add/Mul, and small multi-op chains. Every case runs fp32 and int8.
// The seed is printed on failure with the command that replays it.
#include <sstream>

#include <gtest/gtest.h>

#include "xnnpack/graphs.h"
#include "xnnpack/harness.h"

namespace tlvlink::testing {
namespace {

constexpr int kConvCases = 120;
constexpr int kBinaryCases = 60;
constexpr int kChainCases = 40;

std::string describe(const ConvCase& c) {
  std::ostringstream s;
  s << "conv n=" << c.n << " " << c.h << "x" << c.w << "x" << c.cin << " -> " << c.cout
    << " k=" << c.kh << "x" << c.kw << " s=" << c.stride_h << "," << c.stride_w
    << " d=" << c.dilation_h << " pad=" << c.pad_top << "," << c.pad_bottom << "," << c.pad_left
    << "," << c.pad_right << " groups=" << c.groups << " bias=" << c.bias
    << " act=" << static_cast<int>(c.activation);
  return s.str();
}

std::string describe(const std::vector<int32_t>& shape) {
  std::ostringstream s;
  s << "[";
  for (size_t i = 0; i < shape.size(); ++i) s << (i ? "," : "") << shape[i];
  s << "]";
  return s.str();
}

TEST(XnnpackRandomGraphs, Convolutions) {
  const uint64_t seed = test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  Agreement agg;
  for (int i = 0; i < kConvCases && !::testing::Test::HasFailure(); ++i) {
    const ConvCase c = random_conv_case(rng);
    SCOPED_TRACE("case " + std::to_string(i) + ": " + describe(c));
    check_graph(conv_graph(c, rng), rng, agg);
  }
  std::printf("[ agreement ] %d conv cases: %s\n", kConvCases, agg.summary().c_str());
}

TEST(XnnpackRandomGraphs, BroadcastingAddMul) {
  const uint64_t seed = test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  Agreement agg;
  for (int i = 0; i < kBinaryCases && !::testing::Test::HasFailure(); ++i) {
    const size_t rank = static_cast<size_t>(rng.int_in(1, 4));
    std::vector<int32_t> out(rank), a(rank), b(rank);
    for (size_t d = 0; d < rank; ++d) {
      out[d] = rng.int_in(1, 6);
      a[d] = rng.int_in(0, 3) == 0 ? 1 : out[d];
      b[d] = rng.int_in(0, 2) == 0 ? 1 : out[d];
    }
    const size_t drop = static_cast<size_t>(rng.int_in(0, static_cast<int32_t>(rank) - 1));
    b.erase(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(drop));  // lower-rank operand
    const OpType type = rng.coin() ? OpType::kAdd : OpType::kMul;
    const auto act = static_cast<Activation>(rng.int_in(0, 2));
    const bool constant = rng.coin();
    SCOPED_TRACE("case " + std::to_string(i) + ": " + op_type_name(type) + " " + describe(a) +
                 " x " + describe(b) + (constant ? " (constant)" : ""));
    check_graph(binary_graph(type, a, b, constant, act, rng), rng, agg);
  }
  std::printf("[ agreement ] %d add/mul cases: %s\n", kBinaryCases, agg.summary().c_str());
}

TEST(XnnpackRandomGraphs, Chains) {
  const uint64_t seed = test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  Agreement agg;
  for (int i = 0; i < kChainCases && !::testing::Test::HasFailure(); ++i) {
    SCOPED_TRACE("chain case " + std::to_string(i));
    check_graph(random_chain(rng), rng, agg);
  }
  std::printf("[ agreement ] %d chains: %s\n", kChainCases, agg.summary().c_str());
}

}  // namespace
}  // namespace tlvlink::testing
