// Precomputed text embeddings: the documented directory layout, lookups and every bad file.

#include <gtest/gtest.h>

#include "support/temp_dir.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "tlvlink/io/npy.h"
#include "tlvlink/text/text_encoder.h"

namespace tlvlink::text {
namespace {

namespace fs = std::filesystem;

class PrecomputedEmbeddings : public ::testing::Test {
 protected:
  void SetUp() override {
    write_table("sentence.npy", 2, {3, 4, 0, 0, 0, 0, 0, 2});
    write_table("phrase.npy", 2, {0, 1, 0, 0, 1, 0, 0, 0});
    write_table("prompts.npy", 1, {0, 0, 5, 0});
    write_lines("keys.txt", {"a/0000000001.jpg", "a/0000000002.jpg"});
    write_lines("prompts.txt", {"the object being touched is lifted in the air."});
  }

  void write_table(const std::string& name, int64_t rows, std::vector<float> v) {
    const int64_t dim = static_cast<int64_t>(v.size()) / rows;
    auto a = tools::NpyArray::from<float>({rows, dim}, v);
    ASSERT_TRUE(tools::write_npy((dir_ / name).string(), a).ok());
  }
  void write_lines(const std::string& name, const std::vector<std::string>& lines) {
    std::ofstream out(dir_ / name);
    for (const auto& l : lines) out << l << "\n";
  }
  std::string open_error() {
    auto r = open_precomputed_text_embeddings(dir_.string());
    return r.ok() ? std::string("(opened)") : std::string(r.error().message());
  }
  ::tlvlink::testing::TempDir tmp_{"text"};  // a fresh directory, removed with the fixture
  fs::path dir_ = tmp_.path();
};

TEST_F(PrecomputedEmbeddings, ReadsNormalisesAndLooksUpByKeyAndPrompt) {
  // dim 4 is below kMinTextDim: widen the tables to 8 columns first.
  write_table("sentence.npy", 2, {3, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2});
  write_table("phrase.npy", 2, {0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0});
  write_table("prompts.npy", 1, {0, 0, 5, 0, 0, 0, 0, 0});
  auto enc = open_precomputed_text_embeddings(dir_.string());
  ASSERT_TRUE(enc.ok()) << enc.error().message();
  EXPECT_EQ((*enc)->dim(), 8);
  auto s = (*enc)->embed_sentence("a/0000000001.jpg", "ignored");
  ASSERT_TRUE(s.ok());
  EXPECT_FLOAT_EQ((*s)[0], 0.6f);
  EXPECT_FLOAT_EQ((*s)[1], 0.8f);
  auto y = text_feature(**enc, "a/0000000002.jpg", "x", "y");
  ASSERT_TRUE(y.ok());
  EXPECT_FLOAT_EQ((*y)[0], 1.0f);  // phrase row 1 = e0
  EXPECT_FLOAT_EQ((*y)[7], 1.0f);  // sentence row 1 = 2 e7, normalised
  auto p = (*enc)->embed_prompt("the object being touched is lifted in the air.");
  ASSERT_TRUE(p.ok());
  EXPECT_FLOAT_EQ((*p)[2], 1.0f);
  auto missing = (*enc)->embed_sentence("b/0000000001.jpg", "x");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(std::string(missing.error().message()).find("b/0000000001.jpg"), std::string::npos);
  EXPECT_FALSE((*enc)->embed_prompt("an unknown prompt").ok());
}

TEST_F(PrecomputedEmbeddings, TooSmallDimensionIsAnError) {
  EXPECT_NE(open_error().find("embedding dim 4 outside"), std::string::npos) << open_error();
}

TEST_F(PrecomputedEmbeddings, BadFilesAreNamedErrors) {
  write_table("sentence.npy", 2, std::vector<float>(16, 1.0f));
  write_table("phrase.npy", 2, std::vector<float>(16, 1.0f));
  write_table("prompts.npy", 1, std::vector<float>(8, 1.0f));
  EXPECT_EQ(open_error(), "(opened)");

  write_lines("keys.txt", {"only-one"});
  EXPECT_NE(open_error().find("keys.txt has 1 lines"), std::string::npos) << open_error();
  write_lines("keys.txt", {"dup", "dup"});
  EXPECT_NE(open_error().find("duplicate entry \"dup\""), std::string::npos) << open_error();
  write_lines("keys.txt", {"a", "b"});

  std::vector<float> zero_row(16, 1.0f);
  for (int i = 8; i < 16; ++i) zero_row[static_cast<size_t>(i)] = 0;
  write_table("phrase.npy", 2, zero_row);
  EXPECT_NE(open_error().find("phrase.npy row 1: embedding is all zeros"), std::string::npos)
      << open_error();
  std::vector<float> nan_row(16, 1.0f);
  nan_row[3] = std::nanf("");
  write_table("phrase.npy", 2, nan_row);
  EXPECT_NE(open_error().find("phrase.npy row 0: embedding has NaN/Inf"), std::string::npos)
      << open_error();
  write_table("phrase.npy", 2, std::vector<float>(18, 1.0f));  // dim 9
  EXPECT_NE(open_error().find("dim 9 differs"), std::string::npos) << open_error();
  fs::remove(dir_ / "prompts.npy");
  EXPECT_NE(open_error().find("prompts.npy"), std::string::npos) << open_error();
}

}  // namespace
}  // namespace tlvlink::text
