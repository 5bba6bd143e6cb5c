#pragma once
// Train/test splits that never share a session (Touch-and-Go) or an object (Feel).
//  - Writers use SplitAssigner: the k-th distinct object met is put in the test split so that
//    the first n objects always hold round(n * test_fraction) test objects (exact fractions even
//    for 20 Feel objects; deterministic because generation order is).
//  - Loaders offer a re-split by hash: a key (session or object name) is in the test split iff
//    a 64-bit hash of (key, seed) falls below test_fraction. Depends on nothing but the key, so
//    it is stable under reordering, subsetting and streaming.

#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>

#include "tlvlink/error.h"

namespace tlvlink::datasets {

enum class Split : uint8_t { kAll, kTrain, kTest };
const char* split_name(Split split);  // "all", "train", "test"

struct HashSplit {
  double test_fraction = 0.2;  // [0, 1]
  uint64_t seed = 0;
};
Status validate(const HashSplit& split);
// FNV-1a of the key mixed with the seed (splitmix64), mapped to [0, 1).
double split_hash_unit(std::string_view key, uint64_t seed);
bool hash_split_is_test(std::string_view key, const HashSplit& split);
// True when an item of split `item_is_test` belongs to the requested split.
inline bool split_selects(Split wanted, bool item_is_test) {
  return wanted == Split::kAll || (wanted == Split::kTest) == item_is_test;
}

class SplitAssigner {
 public:
  explicit SplitAssigner(double test_fraction) : test_fraction_(test_fraction) {}
  // Split of `key`, assigning the next slot when the key is new.
  bool is_test(const std::string& key);
  int64_t objects() const { return static_cast<int64_t>(assigned_.size()); }
  int64_t test_objects() const { return test_objects_; }

 private:
  double test_fraction_;
  std::unordered_map<std::string, bool> assigned_;
  int64_t test_objects_ = 0;
};

}  // namespace tlvlink::datasets
