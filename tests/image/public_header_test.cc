// Includes only the image component's umbrella header: compiling proves it is self-contained.
#include "tlvlink/image.h"

#include <gtest/gtest.h>

TEST(ImagePublicHeader, UmbrellaIsSelfContained) {
  EXPECT_STREQ(tlvlink::image::pixel_format_name(tlvlink::image::PixelFormat::kYuyv), "yuyv");
}
