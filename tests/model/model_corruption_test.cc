// Truncated, bit-flipped and foreign files never crash the loader (ASan/UBSan in CI make any
// out-of-bounds read fatal) and produce a clear error.
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/random.h"
#include "support/test_models.h"

namespace tlvlink::testing {
namespace {

TEST(ModelCorruption, BadIdentifierNamed) {
  auto file = TinyInt8Model().build();
  std::memcpy(file.data() + 4, "ONNX", 4);
  // The hash is checked first; with it recomputed, the identifier check names the bytes.
  EXPECT_EQ(load_error(file).code(), ErrorCode::kModelChecksum);
  const Error e = load_error(resealed(file));
  EXPECT_EQ(e.code(), ErrorCode::kModelMalformed);
  EXPECT_NE(std::string(e.message()).find("file identifier is 'ONNX', expected 'TLVM'"),
            std::string::npos)
      << e.message();
  // A foreign file (no trailer, another identifier) is "not a tlvlink model", not a stale one.
  file.resize(file.size() - kTrailerBytes);
  EXPECT_EQ(load_error(file).code(), ErrorCode::kModelMalformed);
}

TEST(ModelCorruption, EveryTruncationRejected) {
  const auto file = TinyInt8Model().build();
  for (size_t n = 0; n < file.size(); ++n) {
    std::vector<std::byte> prefix(file.begin(), file.begin() + static_cast<long>(n));
    const Error e = load_error(prefix);
    ASSERT_NE(e.code(), ErrorCode::kOk)
        << "a " << n << "-byte prefix of a " << file.size() << "-byte model loaded";
  }
}

TEST(ModelCorruption, RandomByteFlipsNeverCrash) {
  const uint64_t seed = test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  const auto file = TinyInt8Model().build();
  int rejected = 0;
  constexpr int kTrials = 3000;
  for (int trial = 0; trial < kTrials; ++trial) {
    auto bad = file;
    const int flips = rng.int_in(1, 4);
    for (int f = 0; f < flips; ++f) {
      const auto pos =
          static_cast<size_t>(rng.int_in(0, static_cast<int32_t>(bad.size() - kTrailerBytes) - 1));
      bad[pos] ^= std::byte(static_cast<uint8_t>(1u << rng.int_in(0, 7)));
    }
    // Resealed, so the flips reach the parser behind the hash (which alone would refuse them all).
    auto result = Model::load(resealed(bad));
    if (!result.ok()) {
      ++rejected;
      EXPECT_GT(std::strlen(result.error().message()), 10u);
    }
  }
  // Most flips land in data the verifier or the semantic checks cover; some (a name, a weight
  // value) are benign to them (the hash catches those: model_integrity_test).
  EXPECT_GT(rejected, kTrials / 2);
}

TEST(ModelCorruption, FlippedWeightByteFailsChecksum) {
  const auto file = TinyInt8Model().build();
  auto model = load_model(file);
  ASSERT_NE(model, nullptr);
  const auto weights = model->graph().tensor(2).data;
  const size_t offset = static_cast<size_t>(weights.data() - model->bytes().data());
  auto bad = file;
  bad[offset + 3] ^= std::byte{0x01};
  const Error e = load_error(bad);
  EXPECT_EQ(e.code(), ErrorCode::kModelChecksum) << e.message();
}

TEST(ModelCorruption, WrongSchemaVersion) {
  TinyInt8Model m;
  m.tweak = [](quantize::ModelBuilder& b) { b.set_schema_version(7); };
  const Error e = load_error(m.build());
  EXPECT_EQ(e.code(), ErrorCode::kModelVersion);
  EXPECT_NE(std::string(e.message()).find("version 7"), std::string::npos);
}

TEST(ModelCorruption, ChecksumCanBeSkippedExplicitly) {
  auto file = TinyInt8Model().build();
  file[100] ^= std::byte{0x10};
  EXPECT_EQ(load_error(file).code(), ErrorCode::kModelChecksum);
  // Fuzzing and tests only: the hash is not compared (the trailer's structure still is).
  auto skipped = Model::load(file, {.verify_checksum = false});
  if (!skipped.ok()) {
    EXPECT_NE(skipped.error().code(), ErrorCode::kModelChecksum);
  }
}

// A file from before the trailer: refused with the command that upgrades it; `upgrade` (and only
// it) may read it, and then the legacy FNV-1a checksum of the constants still applies.
TEST(ModelCorruption, LegacyFileWithoutTrailer) {
  TinyInt8Model m;
  m.tweak = [](quantize::ModelBuilder& b) { b.set_checksum_override(12345); };
  auto bad_fnv = m.build();
  bad_fnv.resize(bad_fnv.size() - kTrailerBytes);
  auto good = TinyInt8Model().build();
  good.resize(good.size() - kTrailerBytes);
  const Error e = load_error(good);
  EXPECT_EQ(e.code(), ErrorCode::kModelChecksum);
  EXPECT_NE(std::string(e.message()).find("tlvlink upgrade"), std::string::npos) << e.message();
  EXPECT_TRUE(Model::load(good, {.accept_legacy = true}).ok());
  const auto legacy = Model::load(bad_fnv, {.accept_legacy = true});
  ASSERT_FALSE(legacy.ok());
  EXPECT_EQ(legacy.error().code(), ErrorCode::kModelChecksum);
  EXPECT_NE(std::string(legacy.error().message()).find("legacy"), std::string::npos);
}

TEST(ModelCorruption, EmptyAndTinyInputs) {
  EXPECT_EQ(load_error({}).code(), ErrorCode::kModelMalformed);
  EXPECT_EQ(load_error(std::vector<std::byte>(7)).code(), ErrorCode::kModelMalformed);
  EXPECT_EQ(load_error(std::vector<std::byte>(64)).code(), ErrorCode::kModelMalformed);
}

}  // namespace
}  // namespace tlvlink::testing
