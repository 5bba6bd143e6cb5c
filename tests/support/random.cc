#include "support/random.h"

#include <cstdlib>
#include <sstream>

namespace tlvlink::testing {

namespace {
constexpr uint64_t kDefaultSeed = 20261122;  // fixed so CI runs are reproducible
}

uint64_t test_seed() {
  if (const char* env = std::getenv("TLVLINK_TEST_SEED"); env != nullptr && *env != '\0') {
    return std::strtoull(env, nullptr, 10);
  }
  return kDefaultSeed;
}

std::string replay_hint(uint64_t seed) {
  std::ostringstream s;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  s << "seed " << seed << "; replay: TLVLINK_TEST_SEED=" << seed << " <test binary>";
  if (info != nullptr) s << " --gtest_filter=" << info->test_suite_name() << "." << info->name();
  return s.str();
}

std::vector<float> Rng::floats(size_t n, float lo, float hi) {
  std::vector<float> v(n);
  for (auto& x : v) x = uniform(lo, hi);
  return v;
}

std::vector<int8_t> Rng::int8s(size_t n, int32_t lo, int32_t hi) {
  std::vector<int8_t> v(n);
  for (auto& x : v) x = static_cast<int8_t>(int_in(lo, hi));
  return v;
}

}  // namespace tlvlink::testing
