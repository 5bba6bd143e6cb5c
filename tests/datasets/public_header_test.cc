// The umbrella header compiles on its own (it is included first, before anything else).
#include "tlvlink/datasets/datasets.h"

#include <gtest/gtest.h>

namespace tlvlink::datasets {
namespace {

TEST(DatasetsHeader, IsSelfContained) {
  LoadReport report;
  EXPECT_EQ(report.summary(), "0 loaded; no problems");
  EXPECT_STREQ(split_name(Split::kTest), "test");
}

}  // namespace
}  // namespace tlvlink::datasets
