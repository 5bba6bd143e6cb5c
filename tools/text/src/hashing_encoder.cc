// The built-in frozen text encoder: a seeded feature-hashing bag of words projected to R^dim.
// Deterministic on every platform: integer hashing and sign bits only, accumulation in double,
// no libm calls except one sqrt (correctly rounded by IEEE 754).

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/text/text_encoder.h"
#include "vector_math.h"

namespace tlvlink::text {
namespace {

// Feature-type weights: whole words carry most meaning; adjacent word pairs add a little
// order; character trigrams tie word forms together ("rough", "roughness").
constexpr double kWordWeight = 1.0;
constexpr double kBigramWeight = 0.5;
constexpr double kTrigramWeight = 0.5;

uint64_t fnv1a(std::string_view s, uint64_t seed) {
  uint64_t h = 0xcbf29ce484222325ULL ^ (seed * 0x9e3779b97f4a7c15ULL);
  for (char c : s) {
    h ^= static_cast<uint8_t>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Lower-case ASCII words of letters and digits; everything else separates words.
std::vector<std::string> words_of(std::string_view text) {
  std::vector<std::string> words;
  std::string current;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if ((u >= 'a' && u <= 'z') || (u >= '0' && u <= '9')) {
      current.push_back(c);
    } else if (u >= 'A' && u <= 'Z') {
      current.push_back(static_cast<char>(u - 'A' + 'a'));
    } else if (!current.empty()) {
      words.push_back(std::move(current));
      current.clear();
    }
  }
  if (!current.empty()) words.push_back(std::move(current));
  return words;
}

// Sublinear term frequency: a word said three times is not three times as important.
double tf_weight(int32_t count) {
  double w = 0;
  for (int32_t c = 1; c <= count; ++c) w += 1.0 / c;  // 1 + 1/2 + ... (harmonic, ~log)
  return w;
}

class HashingTextEncoder final : public TextEncoder {
 public:
  explicit HashingTextEncoder(const HashingTextEncoderOptions& o) : options_(o) {}

  int32_t dim() const override { return options_.dim; }
  std::string description() const override {
    char buf[96];
    std::snprintf(buf, sizeof buf, "hashing-v1(dim=%d,seed=%llu)", options_.dim,
                  static_cast<unsigned long long>(options_.seed));
    return buf;
  }
  Result<std::vector<float>> embed_sentence(const std::string&, const std::string& t) override {
    return embed(t, "sentence");
  }
  Result<std::vector<float>> embed_phrases(const std::string&, const std::string& t) override {
    return embed(t, "phrase description");
  }
  Result<std::vector<float>> embed_prompt(const std::string& t) override {
    return embed(t, "prompt");
  }

 private:
  Result<std::vector<float>> embed(const std::string& text, const char* what) const {
    const std::vector<std::string> words = words_of(text);
    if (words.empty()) {
      return Error::make(ErrorCode::kInvalidArgument, "%s \"%.60s\" has no words to embed", what,
                         text.c_str());
    }
    // feature -> occurrences; the prefix ("w:", "b:", "c:") gives the type and its weight.
    std::map<std::string, int32_t> features;  // ordered: the same sum order everywhere
    for (size_t i = 0; i < words.size(); ++i) {
      ++features["w:" + words[i]];
      if (i + 1 < words.size()) ++features["b:" + words[i] + " " + words[i + 1]];
      const std::string padded = "<" + words[i] + ">";
      for (size_t k = 0; k + 3 <= padded.size(); ++k) ++features["c:" + padded.substr(k, 3)];
    }
    const auto dim = static_cast<size_t>(options_.dim);
    std::vector<double> acc(dim, 0.0);
    for (const auto& [feature, count] : features) {
      const double type_weight = feature[0] == 'w'   ? kWordWeight
                                 : feature[0] == 'b' ? kBigramWeight
                                                     : kTrigramWeight;
      const double w = type_weight * tf_weight(count);
      uint64_t state = fnv1a(feature, options_.seed);
      uint64_t bits = 0;
      for (size_t d = 0; d < dim; ++d) {
        if (d % 64 == 0) bits = splitmix64(state);
        acc[d] += ((bits >> (d % 64)) & 1) ? w : -w;  // Rademacher direction
      }
    }
    std::vector<float> out(dim);
    for (size_t d = 0; d < dim; ++d) out[d] = static_cast<float>(acc[d]);
    TLV_TRY(internal::normalise_in_place(out, what));
    return out;
  }

  HashingTextEncoderOptions options_;
};

}  // namespace

Result<std::unique_ptr<TextEncoder>> make_hashing_text_encoder(
    const HashingTextEncoderOptions& options) {
  if (options.dim < kMinTextDim || options.dim > kMaxTextDim) {
    return Error::make(ErrorCode::kInvalidArgument, "text dim %d outside %d..%d", options.dim,
                       kMinTextDim, kMaxTextDim);
  }
  return std::unique_ptr<TextEncoder>(new HashingTextEncoder(options));
}

}  // namespace tlvlink::text
