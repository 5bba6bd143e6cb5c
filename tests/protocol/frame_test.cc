// One frame: layout, round trip, and every verdict of check_frame (each forged frame gets a
// valid CRC where the check after the CRC is the one under test).
#include <gtest/gtest.h>

#include <vector>

#include "protocol/bytes.h"
#include "tlvlink/protocol/cobs.h"
#include "tlvlink/protocol/crc32.h"
#include "tlvlink/protocol/frame.h"

namespace tlvlink::protocol {
namespace {

using testing::bytes_of;

FrameHeader sample_header() {
  FrameHeader h;
  h.type = MessageType::kFramePrediction;
  h.flags = kFlagDelayed;
  h.sequence = 0x01020304;
  h.send_ns = 0x1122334455667788;
  return h;
}

// The frame before COBS: header || payload || CRC.
std::vector<std::byte> decoded_frame(const FrameHeader& h, std::span<const std::byte> payload) {
  std::vector<std::byte> wire(kMaxWireFrameSize);
  Result<size_t> n = encode_frame(h, payload, wire);
  EXPECT_TRUE(n.ok());
  std::vector<std::byte> out(wire.size());
  Result<size_t> m = cobs_decode(std::span(wire).first(n.value() - 1), out);
  EXPECT_TRUE(m.ok());
  out.resize(m.value());
  return out;
}

// Rewrites the CRC of a decoded frame after a deliberate change (a forgery with a valid CRC).
void recrc(std::vector<std::byte>& f) {
  const uint32_t crc = crc32(std::span(f).first(f.size() - 4));
  for (int i = 0; i < 4; ++i) f[f.size() - 4 + i] = std::byte((crc >> (8 * i)) & 0xFF);
}

FrameVerdict verdict_of(const std::vector<std::byte>& f, FrameHeader* header_out = nullptr) {
  FrameHeader h;
  std::span<const std::byte> payload;
  const FrameVerdict v = check_frame(f, h, payload);
  if (header_out) *header_out = h;
  return v;
}

TEST(Frame, LayoutIsTheSpecified24ByteHeaderPayloadCrc) {
  const auto payload = bytes_of({0xAA, 0x00, 0xBB});
  const auto f = decoded_frame(sample_header(), payload);
  ASSERT_EQ(f.size(), kHeaderSize + payload.size() + kCrcSize);
  EXPECT_EQ(
      std::vector<std::byte>(f.begin(), f.begin() + kHeaderSize),
      bytes_of({0x54, 0x4C, 1, kVersionMinor, 0x02, 0x00, 0x01, 0x00, 0x04, 0x03, 0x02, 0x01, 3,
                0,    0,    0, 0x88,          0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11}));
  EXPECT_EQ(std::vector<std::byte>(f.begin() + kHeaderSize, f.end() - 4), payload);
  const uint32_t crc = crc32(std::span(f).first(f.size() - 4));
  EXPECT_EQ(f[f.size() - 4], std::byte(crc & 0xFF));
  EXPECT_EQ(f[f.size() - 1], std::byte(crc >> 24));
}

TEST(Frame, WireFrameHasOneZeroAtTheEnd) {
  std::vector<std::byte> payload(600, std::byte{0});  // zero-rich, longer than one COBS run
  std::vector<std::byte> wire(kMaxWireFrameSize);
  Result<size_t> n = encode_frame(sample_header(), payload, wire);
  ASSERT_TRUE(n.ok());
  EXPECT_LE(n.value(), cobs_max_encoded_size(kHeaderSize + payload.size() + kCrcSize) + 1);
  for (size_t i = 0; i + 1 < n.value(); ++i) ASSERT_NE(wire[i], std::byte{0}) << i;
  EXPECT_EQ(wire[n.value() - 1], std::byte{0});
}

TEST(Frame, RoundTrip) {
  const auto payload = bytes_of("payload bytes");
  const auto f = decoded_frame(sample_header(), payload);
  FrameHeader h;
  std::span<const std::byte> p;
  ASSERT_EQ(check_frame(f, h, p), FrameVerdict::kOk);
  const FrameHeader want = sample_header();
  EXPECT_EQ(h.type, want.type);
  EXPECT_EQ(h.flags, want.flags);
  EXPECT_EQ(h.sequence, want.sequence);
  EXPECT_EQ(h.send_ns, want.send_ns);
  EXPECT_EQ(h.payload_length, payload.size());
  EXPECT_EQ(std::vector<std::byte>(p.begin(), p.end()), payload);
}

TEST(Frame, EverySingleBitFlipIsRejected) {
  const auto good = decoded_frame(sample_header(), bytes_of("0123456789abcdef0123456789"));
  for (size_t bit = 0; bit < good.size() * 8; ++bit) {
    auto f = good;
    f[bit / 8] ^= std::byte(1u << (bit % 8));
    const FrameVerdict v = verdict_of(f);
    ASSERT_TRUE(v == FrameVerdict::kCrc || v == FrameVerdict::kTruncated)
        << "bit " << bit << ": " << frame_verdict_name(v);
  }
}

TEST(Frame, ForgedCrcIsRejected) {
  auto f = decoded_frame(sample_header(), bytes_of("abc"));
  f[f.size() - 1] ^= std::byte{0x80};
  EXPECT_EQ(verdict_of(f), FrameVerdict::kCrc);
}

TEST(Frame, ForgedLengthWithValidCrcIsRejected) {
  for (uint32_t forged : {0u, 2u, 4u, 1000u, 0xFFFFFFFFu}) {
    auto f = decoded_frame(sample_header(), bytes_of("abc"));
    for (int i = 0; i < 4; ++i) f[12 + i] = std::byte((forged >> (8 * i)) & 0xFF);
    recrc(f);
    EXPECT_EQ(verdict_of(f), FrameVerdict::kLength) << forged;
  }
}

TEST(Frame, CutShortIsTruncated) {
  const auto good =
      decoded_frame(sample_header(), bytes_of("a longer payload, cut at every length"));
  for (size_t n = 0; n < good.size(); ++n) {
    const std::vector<std::byte> f(good.begin(), good.begin() + n);
    const FrameVerdict v = verdict_of(f);
    ASSERT_TRUE(v == FrameVerdict::kTruncated || v == FrameVerdict::kCrc)
        << n << ": " << frame_verdict_name(v);
    if (n >= kHeaderSize + kCrcSize) {
      EXPECT_EQ(v, FrameVerdict::kTruncated) << n;
    }
  }
}

TEST(Frame, WrongMagicWithValidCrc) {
  auto f = decoded_frame(sample_header(), bytes_of("abc"));
  f[0] = std::byte{'X'};
  recrc(f);
  EXPECT_EQ(verdict_of(f), FrameVerdict::kMagic);
}

TEST(Frame, OtherMajorVersionIsRefusedAndNamed) {
  auto f = decoded_frame(sample_header(), bytes_of("abc"));
  f[2] = std::byte{2};
  f[3] = std::byte{7};
  recrc(f);
  FrameHeader h;
  EXPECT_EQ(verdict_of(f, &h), FrameVerdict::kVersion);
  EXPECT_EQ(h.version_major, 2);
  EXPECT_EQ(h.version_minor, 7);
  // A newer minor version of the same major is accepted.
  f[2] = std::byte{kVersionMajor};
  f[3] = std::byte{9};
  recrc(f);
  EXPECT_EQ(verdict_of(f, &h), FrameVerdict::kOk);
  EXPECT_EQ(h.version_minor, 9);
}

TEST(Frame, UnknownFlags) {
  FrameHeader h = sample_header();
  h.flags = 0x0080;  // unknown but ignorable
  EXPECT_EQ(verdict_of(decoded_frame(h, bytes_of("abc"))), FrameVerdict::kOk);
  h.flags = 0x0100;  // must understand
  EXPECT_EQ(verdict_of(decoded_frame(h, bytes_of("abc"))), FrameVerdict::kUnsupportedFlags);
}

TEST(Frame, OversizedPayloadIsNotEncoded) {
  std::vector<std::byte> payload(kMaxPayloadSize + 1, std::byte{1});
  std::vector<std::byte> wire(2 * kMaxWireFrameSize);
  Result<size_t> n = encode_frame(sample_header(), payload, wire);
  ASSERT_FALSE(n.ok());
  EXPECT_EQ(n.error().code(), ErrorCode::kProtocolTooLarge);
  payload.resize(kMaxPayloadSize);
  EXPECT_TRUE(encode_frame(sample_header(), payload, wire).ok());
}

}  // namespace
}  // namespace tlvlink::protocol
