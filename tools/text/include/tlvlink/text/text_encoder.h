#pragma once
// Frozen text encoders for TLV-Link training and zero-shot heads (host side, no libtorch).
//
// Two kinds behind one interface:
//  - HashingTextEncoder, the built-in default: deterministic and seeded, nothing downloaded.
//    Each text becomes a bag of features (lower-cased word unigrams, word bigrams, character
//    trigrams of "<word>"), each feature is hashed (FNV-1a, seeded) to a fixed pseudo-random
//    Gaussian direction in R^dim, and the sublinearly weighted sum is L2-normalised. What it can
//    capture: lexical overlap, shared word stems ("rough"/"roughness"), word order of adjacent
//    pairs. What it cannot: synonyms ("hard"/"rigid" are unrelated), negation ("not soft" is
//    close to "soft"), any meaning a real language model learns. See tools/text/README.md.
//  - PrecomputedTextEmbeddings: embeddings computed elsewhere by any frozen text model, read
//    from the documented directory layout below, looked up by sample key or prompt text.
//
//   auto enc = make_hashing_text_encoder({.dim = 128, .seed = 7});
//   auto f = text_feature(*enc, key, sample.sentence_desc, phrase_desc);  // y = s/|s| + p/|p|
//   auto m = zero_shot_matrix(*enc, material_prompts());                  // [classes, dim]

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::text {

inline constexpr int32_t kMinTextDim = 8;
inline constexpr int32_t kMaxTextDim = 4096;

class TextEncoder {
 public:
  virtual ~TextEncoder() = default;
  virtual int32_t dim() const = 0;
  // "hashing-v1(dim=128,seed=7)" or "precomputed(DIR)": recorded in model provenance.
  virtual std::string description() const = 0;
  // Unit-length embeddings (dim() floats). `key` identifies the sample (the Touch100k `img`) for
  // encoders that look embeddings up; the hashing encoder ignores it. Empty text is an error.
  virtual Result<std::vector<float>> embed_sentence(const std::string& key,
                                                    const std::string& text) = 0;
  virtual Result<std::vector<float>> embed_phrases(const std::string& key,
                                                   const std::string& phrase_desc) = 0;
  virtual Result<std::vector<float>> embed_prompt(const std::string& prompt) = 0;
};

struct HashingTextEncoderOptions {
  int32_t dim = 128;  // kMinTextDim..kMaxTextDim
  uint64_t seed = 7;
};
Result<std::unique_ptr<TextEncoder>> make_hashing_text_encoder(
    const HashingTextEncoderOptions& options);

// Precomputed layout (float32 little-endian .npy, C order):
//   DIR/keys.txt       N lines, the sample keys (Touch100k `img`), unique
//   DIR/sentence.npy   [N, D] sentence-level embeddings, row i for keys.txt line i
//   DIR/phrase.npy     [N, D] phrase-level embeddings
//   DIR/prompts.txt    P lines, prompt texts exactly as zero_shot prompts produce them
//   DIR/prompts.npy    [P, D]
// Rows are L2-normalised on load; a zero, NaN or Inf row is an error naming file and row.
// An unknown key or prompt is an error naming it (never a silent zero vector).
Result<std::unique_ptr<TextEncoder>> open_precomputed_text_embeddings(const std::string& dir);

// The TLV-Link text feature: normalise(sentence) + normalise(phrases) (not re-normalised).
Result<std::vector<float>> text_feature(TextEncoder& encoder, const std::string& key,
                                        const std::string& sentence_desc,
                                        const std::string& phrase_desc);

// Zero-shot prompts of one task: class names and the templates ("{c}" replaced by the class).
struct PromptSet {
  std::string task;  // "material", "hard", "rough", "grasp"
  std::vector<std::string> class_names;
  std::vector<std::string> templates;      // applied to every class ...
  std::vector<std::string> fixed_prompts;  // ... or one literal prompt per class (grasp)
  // The prompts of class i, with {c} substituted.
  std::vector<std::string> prompts_for(size_t class_index) const;
};
// The TLV-Link paper's templates: 20 TAG materials;
// hard/soft; rough/smooth; grasp (lifted in the air / falling on the ground).
PromptSet material_prompts();
PromptSet hardness_prompts();
PromptSet roughness_prompts();
PromptSet grasp_prompts();

// Row-major [classes, dim]: row i = normalise(mean of class i's prompt embeddings).
Result<std::vector<float>> zero_shot_matrix(TextEncoder& encoder, const PromptSet& prompts);

}  // namespace tlvlink::text
