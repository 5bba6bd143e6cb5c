// CRC-32 against its published check value and zlib's results; COBS against the encoding
// examples of Cheshire & Baker's paper / the Wikipedia table, seeded random round trips, the
// size bound, and malformed input.
#include <gtest/gtest.h>

#include <vector>

#include "protocol/bytes.h"
#include "support/random.h"
#include "tlvlink/protocol/cobs.h"
#include "tlvlink/protocol/crc32.h"

namespace tlvlink::protocol {
namespace {

using testing::bytes_of;

TEST(Crc32, CheckValueAndZlibVectors) {
  EXPECT_EQ(crc32(bytes_of("123456789")), 0xCBF43926u);  // the CRC-32/ISO-HDLC check value
  EXPECT_EQ(crc32({}), 0u);
  // zlib.crc32(b"The quick brown fox jumps over the lazy dog")
  EXPECT_EQ(crc32(bytes_of("The quick brown fox jumps over the lazy dog")), 0x414FA339u);
  const auto all = bytes_of("123456789");
  EXPECT_EQ(crc32(std::span(all).subspan(4), crc32(std::span(all).first(4))), 0xCBF43926u);
}

std::vector<std::byte> encode(std::span<const std::byte> in) {
  std::vector<std::byte> out(cobs_max_encoded_size(in.size()));
  CobsEncoder e(out);
  e.put(in);
  Result<size_t> n = e.finish();
  EXPECT_TRUE(n.ok()) << n.error().message();
  out.resize(n.ok() ? n.value() : 0);
  return out;
}

std::vector<std::byte> run(int first, int last) {
  std::vector<std::byte> v;
  for (int i = first; i <= last; ++i) v.push_back(static_cast<std::byte>(i));
  return v;
}

TEST(Cobs, PublishedExamples) {
  EXPECT_EQ(encode(bytes_of({0x00})), bytes_of({0x01, 0x01}));
  EXPECT_EQ(encode(bytes_of({0x00, 0x00})), bytes_of({0x01, 0x01, 0x01}));
  EXPECT_EQ(encode(bytes_of({0x00, 0x11, 0x00})), bytes_of({0x01, 0x02, 0x11, 0x01}));
  EXPECT_EQ(encode(bytes_of({0x11, 0x22, 0x00, 0x33})), bytes_of({0x03, 0x11, 0x22, 0x02, 0x33}));
  EXPECT_EQ(encode(bytes_of({0x11, 0x22, 0x33, 0x44})), bytes_of({0x05, 0x11, 0x22, 0x33, 0x44}));
  EXPECT_EQ(encode(bytes_of({0x11, 0x00, 0x00, 0x00})), bytes_of({0x02, 0x11, 0x01, 0x01, 0x01}));
  // 254 non-zero bytes: one full run, no trailing code byte.
  std::vector<std::byte> expect = bytes_of({0xFF});
  const auto r254 = run(0x01, 0xFE);
  expect.insert(expect.end(), r254.begin(), r254.end());
  EXPECT_EQ(encode(r254), expect);
  // 00 01 .. FE: a zero, then a full run.
  std::vector<std::byte> in = bytes_of({0x00});
  in.insert(in.end(), r254.begin(), r254.end());
  expect.insert(expect.begin(), std::byte{0x01});
  EXPECT_EQ(encode(in), expect);
  // 01 .. FF: a full run, then one more byte.
  const auto r255 = run(0x01, 0xFF);
  std::vector<std::byte> expect255 = bytes_of({0xFF});
  expect255.insert(expect255.end(), r254.begin(), r254.end());
  expect255.push_back(std::byte{0x02});
  expect255.push_back(std::byte{0xFF});
  EXPECT_EQ(encode(r255), expect255);
}

TEST(Cobs, RandomRoundTripsStayWithinTheBound) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  for (int iter = 0; iter < 2000; ++iter) {
    const size_t n = static_cast<size_t>(rng.int_in(0, 1200));
    const int zero_permille = rng.int_in(0, 3) * 300;  // none, some, many, most zeros
    std::vector<std::byte> in(n);
    for (auto& b : in)
      b = rng.int_in(0, 999) < zero_permille ? std::byte{0} : std::byte(rng.int_in(1, 255));
    const auto enc = encode(in);
    ASSERT_LE(enc.size(), cobs_max_encoded_size(n));
    for (std::byte b : enc) ASSERT_NE(b, std::byte{0});
    std::vector<std::byte> dec(enc.size());
    Result<size_t> m = cobs_decode(enc, dec);
    ASSERT_TRUE(m.ok()) << m.error().message();
    dec.resize(m.value());
    ASSERT_EQ(dec, in) << "n=" << n;
  }
}

TEST(Cobs, EncoderRefusesASmallBuffer) {
  std::vector<std::byte> out(4);
  CobsEncoder e(out);
  e.put(run(1, 10));
  Result<size_t> n = e.finish();
  ASSERT_FALSE(n.ok());
  EXPECT_EQ(n.error().code(), ErrorCode::kProtocolTooLarge);
}

TEST(Cobs, DecoderRejectsRunsPastTheEnd) {
  std::vector<std::byte> out(16);
  Result<size_t> n = cobs_decode(bytes_of({0x05, 0x11, 0x22}), out);
  ASSERT_FALSE(n.ok());
  EXPECT_EQ(n.error().code(), ErrorCode::kProtocolMalformed);
  EXPECT_NE(std::string(n.error().message()).find("past the end"), std::string::npos)
      << n.error().message();
  EXPECT_FALSE(cobs_decode(bytes_of({0x02, 0x00}), out).ok());  // a zero inside
  std::vector<std::byte> tiny(2);
  EXPECT_EQ(cobs_decode(bytes_of({0x05, 1, 2, 3, 4}), tiny).error().code(),
            ErrorCode::kProtocolTooLarge);
}

}  // namespace
}  // namespace tlvlink::protocol
