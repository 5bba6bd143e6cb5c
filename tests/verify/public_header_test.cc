// Includes only the verify component's umbrella header: compiling proves it is self-contained.
#include "tlvlink/verify.h"

#include <array>
#include <cstring>

#include <gtest/gtest.h>

TEST(VerifyPublicHeader, UmbrellaIsSelfContained) {
  tlvlink::Tensor t;
  t.dtype = tlvlink::DType::kFloat32;
  t.shape.rank = 1;
  t.shape.dims[0] = 2;
  const std::array<float, 2> values{1.5f, -2.0f};
  std::array<std::byte, 8> bytes{};
  std::memcpy(bytes.data(), values.data(), bytes.size());
  EXPECT_EQ(tlvlink::verify::output_value(t, bytes, 1), -2.0f);
}
