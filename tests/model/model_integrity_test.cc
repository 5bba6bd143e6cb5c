// The integrity trailer on the shipped int8 model: single-bit flips anywhere are refused at
// load, signatures (unsigned / another key / tampered / good), files from before the trailer
// refused with the upgrade command and upgraded to the same model, golden head outputs checked.
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "support/random.h"
#include "support/test_models.h"
#include "tlvlink/model_integrity.h"
#include "tlvlink/quantize/model_sign.h"
#include "tlvlink/verify/golden_heads.h"

namespace tlvlink::testing {
namespace {

constexpr const char* kShipped = TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm";

std::vector<std::byte> shipped() {
  std::vector<std::byte> bytes;
  std::FILE* f = std::fopen(kShipped, "rb");
  if (f == nullptr) return bytes;
  std::byte chunk[1 << 16];
  size_t n = 0;
  while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0)
    bytes.insert(bytes.end(), chunk, chunk + n);
  std::fclose(f);
  return bytes;
}

std::vector<std::byte> flipped(std::vector<std::byte> file, size_t bit) {
  file[bit / 8] ^= std::byte(static_cast<uint8_t>(1u << (bit % 8)));
  return file;
}

// Offset of `p` (a view into the loaded model) in the file.
size_t offset_of(const Model& m, const void* p) {
  return static_cast<size_t>(static_cast<const std::byte*>(p) - m.bytes().data());
}

class ShippedModel : public ::testing::Test {
 protected:
  void SetUp() override {
    file_ = shipped();
    ASSERT_GT(file_.size(), kTrailerBytes) << kShipped;
    model_ = load_model(file_);
    ASSERT_NE(model_, nullptr);
  }
  std::vector<std::byte> file_;
  std::unique_ptr<Model> model_;
};

TEST_F(ShippedModel, HasAnUnsignedTrailer) {
  EXPECT_EQ(model_->integrity().body_size, file_.size() - kTrailerBytes);
  EXPECT_FALSE(model_->integrity().is_signed);
}

// A seeded sample over every region: the file in 2,048 equal strata, one flip in each, plus
// 1,024 uniform flips.
TEST_F(ShippedModel, SampledSingleBitFlipsAllRefused) {
  const uint64_t seed = test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  const size_t bits = file_.size() * 8;
  constexpr size_t kStrata = 2048, kUniform = 1024;
  std::vector<size_t> sample;
  for (size_t k = 0; k < kStrata; ++k) {
    const size_t width = bits / kStrata;
    sample.push_back(k * width +
                     static_cast<size_t>(rng.int_in(0, static_cast<int32_t>(width) - 1)));
  }
  for (size_t k = 0; k < kUniform; ++k) {
    sample.push_back(static_cast<size_t>(rng.int_in(0, static_cast<int32_t>(bits - 1))));
  }
  for (size_t bit : sample) {
    const Error e = load_error(flipped(file_, bit));
    ASSERT_EQ(e.code(), ErrorCode::kModelChecksum) << "bit " << bit << ": " << e.message();
  }
}

TEST_F(ShippedModel, EveryTrailerBitFlipRefused) {
  for (size_t bit = (file_.size() - kTrailerBytes) * 8; bit < file_.size() * 8; ++bit) {
    const Error e = load_error(flipped(file_, bit));
    ASSERT_NE(e.code(), ErrorCode::kOk)
        << "trailer bit " << bit - (file_.size() - kTrailerBytes) * 8;
  }
}

// Every bit of the first 8 bytes of each head's parameters, the input spec's mean/std, a label,
// and the golden head outputs: the places where flips used to change predictions silently.
TEST_F(ShippedModel, TargetedFlipsInHeadsInputSpecLabelsRefused) {
  const Metadata& m = model_->metadata();
  ASSERT_FALSE(m.linear_heads.empty());
  ASSERT_TRUE(m.grasp_head.present);
  ASSERT_FALSE(m.golden.empty());
  ASSERT_FALSE(m.golden[0].head_probabilities.empty());
  std::vector<std::pair<const char*, const void*>> targets = {
      {"probe weight", m.linear_heads[0].weight.data()},
      {"probe bias", m.linear_heads[0].bias.data()},
      {"label", m.linear_heads[0].labels[0].data()},
      {"grasp weight", m.grasp_head.weight.data()},
      {"input mean", m.input.mean.data()},
      {"input std", m.input.std.data()},
      {"golden head outputs", m.golden[0].head_probabilities.data()},
  };
  if (!m.zero_shot_heads.empty())
    targets.push_back({"prompt matrix", m.zero_shot_heads[0].prompt_matrix.data()});
  for (const auto& [what, p] : targets) {
    const size_t at = offset_of(*model_, p);
    for (size_t bit = at * 8; bit < at * 8 + 64; ++bit) {
      const Error e = load_error(flipped(file_, bit));
      ASSERT_EQ(e.code(), ErrorCode::kModelChecksum) << what << " bit " << bit - at * 8;
      EXPECT_NE(std::string(e.message()).find("integrity check failed"), std::string::npos)
          << e.message();
    }
  }
}

TEST_F(ShippedModel, GoldenHeadOutputsStoredAndChecked) {
  auto check = verify::check_golden_heads(*model_);
  ASSERT_TRUE(check.ok()) << check.error().message();
  EXPECT_TRUE(check->stored);
  EXPECT_TRUE(check->pass) << check->max_abs_error;
  EXPECT_TRUE(model_->metadata().has_golden_grasp);
  // A stored probability moved by 0.01 (file resealed, so only verify can notice): refused.
  auto bad = file_;
  const size_t at = offset_of(*model_, model_->metadata().golden[0].head_probabilities.data());
  float v;
  std::memcpy(&v, bad.data() + at, sizeof v);
  v += 0.01f;
  std::memcpy(bad.data() + at, &v, sizeof v);
  auto edited = load_model(resealed(bad));
  ASSERT_NE(edited, nullptr);
  auto edited_check = verify::check_golden_heads(*edited);
  ASSERT_TRUE(edited_check.ok());
  EXPECT_FALSE(edited_check->pass);
  EXPECT_GT(edited_check->max_abs_error, 0.009);
}

TEST_F(ShippedModel, Signatures) {
  auto keys = quantize::generate_keypair();
  auto other = quantize::generate_keypair();
  ASSERT_TRUE(keys.ok() && other.ok());
  const LoadOptions with_key{.public_key = &keys->public_key};
  // Unsigned, with a key required.
  Error e = Model::load(file_, with_key).error();
  EXPECT_EQ(e.code(), ErrorCode::kModelSignature);
  EXPECT_NE(std::string(e.message()).find("not signed"), std::string::npos) << e.message();
  // Good.
  auto signed_file = quantize::sign_model(file_, keys->secret);
  ASSERT_TRUE(signed_file.ok()) << signed_file.error().message();
  auto good = Model::load(*signed_file, with_key);
  ASSERT_TRUE(good.ok()) << good.error().message();
  EXPECT_TRUE((*good)->integrity().is_signed);
  EXPECT_TRUE(Model::load(*signed_file).ok()) << "a signed file loads without a key too";
  // Another key: both ids named.
  e = Model::load(*signed_file, {.public_key = &other->public_key}).error();
  EXPECT_EQ(e.code(), ErrorCode::kModelSignature);
  char id[17];
  to_hex(key_id(keys->public_key), id, sizeof id);
  EXPECT_NE(std::string(e.message()).find(id), std::string::npos) << e.message();
  // Tampered after signing: a body bit (hash), the flags (hash), the signature itself.
  const size_t trailer = signed_file->size() - kTrailerBytes;
  EXPECT_EQ(Model::load(flipped(*signed_file, 1000), with_key).error().code(),
            ErrorCode::kModelChecksum);
  EXPECT_EQ(Model::load(flipped(*signed_file, (trailer + 6) * 8), with_key).error().code(),
            ErrorCode::kModelChecksum);
  e = Model::load(flipped(*signed_file, (trailer + 60) * 8), with_key).error();
  EXPECT_EQ(e.code(), ErrorCode::kModelSignature);
  EXPECT_NE(std::string(e.message()).find("does not verify"), std::string::npos) << e.message();
  // A body edited and resealed by someone without the key: the signature no longer verifies.
  auto forged = flipped(*signed_file, 1000);
  forged = seal_model(std::span<const std::byte>(forged).first(trailer));
  EXPECT_EQ(Model::load(forged, with_key).error().code(), ErrorCode::kModelSignature);
}

TEST(KeyFiles, RoundTripAndRefusals) {
  auto keys = quantize::generate_keypair();
  ASSERT_TRUE(keys.ok());
  const std::string pub = quantize::format_public_key(keys->public_key);
  const std::string sec = quantize::format_secret_key(keys->secret);
  auto p = parse_public_key(pub);
  auto s = parse_secret_key(sec);
  ASSERT_TRUE(p.ok() && s.ok());
  EXPECT_EQ(p->bytes, keys->public_key.bytes);
  EXPECT_EQ(public_half(*s).bytes, keys->public_key.bytes);
  EXPECT_FALSE(parse_public_key(sec).ok()) << "a secret key is not a public key";
  EXPECT_FALSE(parse_secret_key(pub).ok());
  std::string damaged = sec;
  damaged[damaged.size() - 3] = damaged[damaged.size() - 3] == '0' ? '1' : '0';  // public half
  EXPECT_FALSE(parse_secret_key(damaged).ok());
}

TEST_F(ShippedModel, LegacyFileRefusedThenUpgradedToTheSameModel) {
  // A file from before the trailer: the flatbuffer alone (its FNV checksum is still written).
  const std::vector<std::byte> legacy(file_.begin(),
                                      file_.end() - static_cast<long>(kTrailerBytes));
  const Error e = load_error(legacy);
  EXPECT_EQ(e.code(), ErrorCode::kModelChecksum);
  EXPECT_NE(std::string(e.message()).find("tlvlink upgrade"), std::string::npos) << e.message();
  EXPECT_TRUE(Model::load(legacy, {.accept_legacy = true}).ok());
  auto upgraded = quantize::upgrade_model(legacy);
  ASSERT_TRUE(upgraded.ok()) << upgraded.error().message();
#if defined(__x86_64__)
  // Writing the same model again gives the same bytes: the shipped file (written on x86-64) is
  // a fixed point.
  EXPECT_EQ(*upgraded, file_);
#else
  // Elsewhere the rewrite recomputes the golden head outputs with this CPU's float math (expf,
  // fused multiply-add), so bytes may differ; the outputs must agree within verify's tolerance.
  auto again = Model::load(*upgraded);
  ASSERT_TRUE(again.ok()) << again.error().message();
  const Metadata& a = (*again)->metadata();
  const Metadata& b = model_->metadata();
  ASSERT_EQ(a.golden.size(), b.golden.size());
  for (size_t p = 0; p < a.golden.size(); ++p) {
    ASSERT_EQ(a.golden[p].head_probabilities.size(), b.golden[p].head_probabilities.size());
    for (size_t i = 0; i < a.golden[p].head_probabilities.size(); ++i)
      EXPECT_NEAR(a.golden[p].head_probabilities[i], b.golden[p].head_probabilities[i], 1e-3);
  }
  EXPECT_NEAR(a.golden_grasp, b.golden_grasp, 1e-3);
#endif
  // A legacy file whose constants were altered: the legacy checksum still refuses it.
  const size_t w = offset_of(
      *model_, model_->graph().tensor(model_->graph().operators[0].inputs[1]).data.data());
  const Error altered = Model::load(flipped(legacy, w * 8), {.accept_legacy = true}).error();
  EXPECT_EQ(altered.code(), ErrorCode::kModelChecksum) << altered.message();
}

}  // namespace
}  // namespace tlvlink::testing
