// Includes only the pipeline component's umbrella header: compiling proves it is self-contained.
#include "tlvlink/pipeline.h"

#include <gtest/gtest.h>

TEST(PipelinePublicHeader, UmbrellaIsSelfContained) {
  EXPECT_STREQ(tlvlink::pipeline::contact_state_name(tlvlink::pipeline::ContactState::kContact),
               "contact");
}
