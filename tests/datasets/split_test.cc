// Split helpers: exact ordinal assignment for writers, deterministic hash re-split for loaders.

#include "tlvlink/datasets/split.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tlvlink/datasets/report.h"

namespace tlvlink::datasets {
namespace {

TEST(SplitAssigner, HoldsRoundedFractionAtEveryPrefix) {
  SplitAssigner s(0.2);
  int64_t test = 0;
  for (int k = 0; k < 50; ++k) {
    test += s.is_test("object" + std::to_string(k)) ? 1 : 0;
    EXPECT_EQ(test, static_cast<int64_t>(std::floor((k + 1) * 0.2 + 0.5))) << "after " << k + 1;
  }
  EXPECT_EQ(s.test_objects(), 10);
  // A key seen before keeps its split.
  EXPECT_EQ(s.is_test("object4"), s.is_test("object4"));
  EXPECT_EQ(s.objects(), 50);
}

TEST(SplitAssigner, ZeroAndOneFractions) {
  SplitAssigner none(0.0), all(1.0);
  for (int k = 0; k < 10; ++k) {
    EXPECT_FALSE(none.is_test(std::to_string(k)));
    EXPECT_TRUE(all.is_test(std::to_string(k)));
  }
}

TEST(HashSplit, DeterministicAndNearTheFraction) {
  const HashSplit split{0.25, 42};
  int test = 0;
  for (int k = 0; k < 2000; ++k) {
    const std::string key = "2022010" + std::to_string(k % 9) + "_" + std::to_string(100000 + k);
    const bool t = hash_split_is_test(key, split);
    EXPECT_EQ(t, hash_split_is_test(key, split));
    test += t ? 1 : 0;
  }
  // Binomial(2000, 0.25): sd ~ 19, so +-100 is > 5 sd.
  EXPECT_NEAR(test, 500, 100);
  // Another seed gives another split.
  int differ = 0;
  for (int k = 0; k < 200; ++k)
    differ += hash_split_is_test(std::to_string(k), split) !=
              hash_split_is_test(std::to_string(k), HashSplit{0.25, 43});
  EXPECT_GT(differ, 0);
  EXPECT_FALSE(validate(HashSplit{1.5, 0}).ok());
  EXPECT_FALSE(validate(HashSplit{std::nan(""), 0}).ok());
}

TEST(LoadReport, CountsAllKeepsFirstAndCallsBack) {
  LoadReport r(2);
  int calls = 0;
  r.on_problem = [&](const LoadProblem&) { ++calls; };
  r.add({ProblemKind::kMissingFile, "a.jpg", 0, "not found"});
  r.add({ProblemKind::kMalformedLine, "list.json", 7, "bad"});
  r.add({ProblemKind::kMissingFile, "b.jpg", 0, "not found"});
  r.count_loaded();
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(r.problems().size(), 2u);
  EXPECT_EQ(r.missing_files(), 2);
  EXPECT_EQ(r.problems()[1].to_string(), "list.json:7: malformed line: bad");
  EXPECT_EQ(r.summary(), "1 loaded; 2 missing files, 1 malformed line");
}

}  // namespace
}  // namespace tlvlink::datasets
