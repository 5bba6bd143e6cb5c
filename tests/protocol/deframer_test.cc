// The receiving side under damage: garbage, truncation, bit flips, oversized segments, forged
// lengths and CRCs. Each is rejected and counted, and the next good frame is decoded. Random
// cases are seeded (TLVLINK_TEST_SEED replays them).
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "protocol/bytes.h"
#include "support/random.h"
#include "tlvlink/protocol/cobs.h"
#include "tlvlink/protocol/crc32.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/frame.h"

namespace tlvlink::protocol {
namespace {

struct Collected {
  std::vector<FrameHeader> headers;
  std::vector<std::vector<std::byte>> payloads;
  std::vector<FrameVerdict> verdicts;  // every segment, good or not
};

// A frame whose payload says which sequence it is, so a receiver can check any frame it accepts.
std::vector<std::byte> payload_for(uint32_t seq, size_t size) {
  std::vector<std::byte> p(size);
  for (size_t i = 0; i < size; ++i) p[i] = std::byte((seq * 131 + i * 7) & 0xFF);
  return p;
}

std::vector<std::byte> wire_frame(uint32_t seq, size_t payload_size) {
  FrameHeader h;
  h.type = MessageType::kStats;
  h.sequence = seq;
  h.send_ns = 1000 + seq;
  std::vector<std::byte> out(kMaxWireFrameSize);
  Result<size_t> n = encode_frame(h, payload_for(seq, payload_size), out);
  EXPECT_TRUE(n.ok());
  out.resize(n.value());
  return out;
}

void feed(Deframer& d, std::span<const std::byte> bytes, Collected& c) {
  d.feed(bytes, [&](const ReceivedFrame& f) {
    c.verdicts.push_back(f.verdict);
    if (f.verdict != FrameVerdict::kOk) return;
    c.headers.push_back(f.header);
    c.payloads.emplace_back(f.payload.begin(), f.payload.end());
    EXPECT_EQ(reinterpret_cast<uintptr_t>(f.payload.data()) % 8, 0u);
  });
}

TEST(Deframer, ChunkedStreamDecodesEveryFrame) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  std::vector<std::byte> stream;
  for (uint32_t s = 0; s < 200; ++s) {
    const auto f = wire_frame(s, static_cast<size_t>(rng.int_in(0, 700)));
    stream.insert(stream.end(), f.begin(), f.end());
  }
  Deframer d;
  Collected c;
  for (size_t i = 0; i < stream.size();) {
    const size_t n = std::min(stream.size() - i, static_cast<size_t>(rng.int_in(1, 300)));
    feed(d, std::span(stream).subspan(i, n), c);
    i += n;
  }
  ASSERT_EQ(c.headers.size(), 200u);
  for (uint32_t s = 0; s < 200; ++s) {
    EXPECT_EQ(c.headers[s].sequence, s);
    EXPECT_EQ(c.payloads[s], payload_for(s, c.payloads[s].size()));
  }
  EXPECT_EQ(d.counters().frames, 200u);
  EXPECT_EQ(d.counters().rejected(), 0u);
  EXPECT_EQ(d.counters().bytes, stream.size());
}

TEST(Deframer, ResyncsAfterGarbage) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  Deframer d;
  Collected c;
  for (uint32_t s = 0; s < 50; ++s) {
    std::vector<std::byte> garbage(static_cast<size_t>(rng.int_in(1, 500)));
    for (auto& b : garbage) b = std::byte(rng.int_in(0, 255));
    garbage.push_back(std::byte{0});  // garbage ends somewhere; the sender's next frame follows
    feed(d, garbage, c);
    feed(d, wire_frame(s, 40), c);
  }
  ASSERT_EQ(c.headers.size(), 50u);
  for (uint32_t s = 0; s < 50; ++s) EXPECT_EQ(c.headers[s].sequence, s);
  EXPECT_GT(d.counters().rejected(), 0u);
  EXPECT_GT(d.counters().discarded_bytes, 0u);
}

TEST(Deframer, TruncatedFramesAreRejectedAndTheNextDecoded) {
  Deframer d;
  Collected c;
  // Cut in the middle with the delimiter kept (bytes lost in the middle of a frame).
  auto f0 = wire_frame(0, 100);
  f0.erase(f0.begin() + 30, f0.begin() + 60);
  feed(d, f0, c);
  feed(d, wire_frame(1, 100), c);
  // Cut before its delimiter: the rest merges with the next frame, which is lost with it; the
  // frame after that is decoded.
  auto f2 = wire_frame(2, 100);
  f2.resize(50);
  feed(d, f2, c);
  feed(d, wire_frame(3, 100), c);
  feed(d, wire_frame(4, 100), c);
  ASSERT_EQ(c.headers.size(), 2u);
  EXPECT_EQ(c.headers[0].sequence, 1u);
  EXPECT_EQ(c.headers[1].sequence, 4u);
  EXPECT_EQ(d.counters().rejected(), 2u);
}

TEST(Deframer, BitFlipsNeverYieldACorruptedFrame) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  std::vector<std::byte> stream;
  std::map<uint32_t, size_t> sizes;
  for (uint32_t s = 0; s < 2000; ++s) {
    sizes[s] = static_cast<size_t>(rng.int_in(0, 300));
    const auto f = wire_frame(s, sizes[s]);
    stream.insert(stream.end(), f.begin(), f.end());
  }
  size_t flips = 0;
  for (auto& b : stream) {
    if (rng.int_in(0, 999) < 2) {  // 2 per mille of bytes get one flipped bit
      b ^= std::byte(1u << rng.int_in(0, 7));
      ++flips;
    }
  }
  Deframer d;
  Collected c;
  feed(d, stream, c);
  for (size_t i = 0; i < c.headers.size(); ++i) {
    const uint32_t s = c.headers[i].sequence;
    ASSERT_TRUE(sizes.count(s)) << "accepted a frame with a sequence never sent: " << s;
    ASSERT_EQ(c.payloads[i], payload_for(s, sizes[s]))
        << "accepted a corrupted frame, sequence " << s;
  }
  EXPECT_LT(c.headers.size(), 2000u);
  EXPECT_GT(c.headers.size(), 1000u) << flips << " flips";
  EXPECT_GT(d.counters().rejected(), 0u);
}

TEST(Deframer, OversizedSegmentIsDroppedThenResyncs) {
  Deframer d;
  Collected c;
  std::vector<std::byte> big(kMaxWireFrameSize + 100, std::byte{0x55});
  feed(d, std::span(big).first(5000), c);  // arrives in pieces
  feed(d, std::span(big).subspan(5000), c);
  feed(d, wire_frame(7, 10), c);  // its delimiter ends the oversized segment first
  ASSERT_EQ(c.verdicts.size(), 1u);
  EXPECT_EQ(c.verdicts[0], FrameVerdict::kOversized);
  feed(d, wire_frame(8, 10), c);
  ASSERT_EQ(c.headers.size(), 1u);
  EXPECT_EQ(c.headers[0].sequence, 8u);
  EXPECT_EQ(d.counters().oversized, 1u);
  EXPECT_EQ(d.counters().discarded_bytes, big.size() + wire_frame(7, 10).size() - 1);
}

TEST(Deframer, LargestFrameIsAccepted) {
  Deframer d;
  Collected c;
  feed(d, wire_frame(1, kMaxPayloadSize), c);
  ASSERT_EQ(c.headers.size(), 1u);
  EXPECT_EQ(c.payloads[0].size(), kMaxPayloadSize);
}

// Re-encodes a decoded frame after a change, with or without a correct CRC.
std::vector<std::byte> forge(uint32_t seq, size_t length_field, bool fix_crc, bool break_crc) {
  auto wire = wire_frame(seq, 64);
  std::vector<std::byte> f(wire.size());
  Result<size_t> n = cobs_decode(std::span(wire).first(wire.size() - 1), f);
  EXPECT_TRUE(n.ok());
  f.resize(n.value());
  for (int i = 0; i < 4; ++i) f[12 + i] = std::byte((length_field >> (8 * i)) & 0xFF);
  if (fix_crc) {
    const uint32_t crc = crc32(std::span(f).first(f.size() - 4));
    for (int i = 0; i < 4; ++i) f[f.size() - 4 + i] = std::byte((crc >> (8 * i)) & 0xFF);
  }
  if (break_crc) f[f.size() - 2] ^= std::byte{0x10};
  std::vector<std::byte> out(cobs_max_encoded_size(f.size()) + 1);
  CobsEncoder e{std::span(out).first(out.size() - 1)};
  e.put(f);
  Result<size_t> m = e.finish();
  EXPECT_TRUE(m.ok());
  out[m.value()] = std::byte{0};
  out.resize(m.value() + 1);
  return out;
}

TEST(Deframer, ForgedLengthsAndCrcsAreRejected) {
  Deframer d;
  Collected c;
  feed(d, forge(0, 10'000, /*fix_crc=*/true, false), c);  // length lies, CRC recomputed
  feed(d, forge(1, 0, true, false), c);
  feed(d, forge(2, 64, false, /*break_crc=*/true), c);  // right length, CRC forged
  feed(d, forge(3, 1'000'000, false, false), c);        // length lies, CRC stale
  feed(d, wire_frame(4, 64), c);
  ASSERT_EQ(c.headers.size(), 1u);
  EXPECT_EQ(c.headers[0].sequence, 4u);
  EXPECT_EQ(d.counters().length, 2u);
  EXPECT_EQ(d.counters().crc + d.counters().truncated, 2u);
}

TEST(Deframer, RunsOfDelimitersAreNotFrames) {
  Deframer d;
  Collected c;
  std::vector<std::byte> zeros(100, std::byte{0});
  feed(d, zeros, c);
  feed(d, wire_frame(1, 5), c);
  feed(d, zeros, c);
  EXPECT_EQ(c.verdicts.size(), 1u);
  EXPECT_EQ(d.counters().rejected(), 0u);
}

TEST(Deframer, ResetForgetsAPartialFrame) {
  Deframer d;
  Collected c;
  const auto f = wire_frame(1, 50);
  feed(d, std::span(f).first(20), c);
  d.reset();  // the link dropped and came back
  feed(d, wire_frame(2, 50), c);
  ASSERT_EQ(c.headers.size(), 1u);
  EXPECT_EQ(c.headers[0].sequence, 2u);
  EXPECT_EQ(d.counters().rejected(), 0u);
}

}  // namespace
}  // namespace tlvlink::protocol
