// The public umbrella header compiles on its own (no include-order dependency).
#include "tlvlink/eval/eval.h"

#include <gtest/gtest.h>

TEST(EvalPublicHeader, SelfContained) {
  EXPECT_STREQ(tlvlink::eval::task_name(tlvlink::eval::Task::kGrasp), "grasp");
  EXPECT_EQ(tlvlink::eval::paper_table2().size(), 3u);
}
