#include "tlvlink/datasets/split.h"

#include <cmath>

namespace tlvlink::datasets {
namespace {

uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace

const char* split_name(Split split) {
  switch (split) {
    case Split::kAll: return "all";
    case Split::kTrain: return "train";
    case Split::kTest: return "test";
  }
  return "?";
}

Status validate(const HashSplit& split) {
  TLV_ENSURE(
      std::isfinite(split.test_fraction) && split.test_fraction >= 0 && split.test_fraction <= 1,
      ErrorCode::kInvalidArgument, "test_fraction %g outside [0, 1]", split.test_fraction);
  return {};
}

double split_hash_unit(std::string_view key, uint64_t seed) {
  uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a offset basis
  for (char c : key) {
    h ^= static_cast<uint8_t>(c);
    h *= 0x100000001b3ULL;
  }
  // 53 high bits -> a double in [0, 1).
  return static_cast<double>(splitmix64(h ^ splitmix64(seed)) >> 11) * 0x1.0p-53;
}

bool hash_split_is_test(std::string_view key, const HashSplit& split) {
  return split_hash_unit(key, split.seed) < split.test_fraction;
}

bool SplitAssigner::is_test(const std::string& key) {
  if (auto it = assigned_.find(key); it != assigned_.end()) return it->second;
  // Objects 0..k-1 hold round(k * f) test objects; object k is test iff that count grows.
  const auto k = static_cast<double>(assigned_.size());
  const bool test =
      std::floor((k + 1) * test_fraction_ + 0.5) > std::floor(k * test_fraction_ + 0.5);
  assigned_.emplace(key, test);
  if (test) ++test_objects_;
  return test;
}

}  // namespace tlvlink::datasets
