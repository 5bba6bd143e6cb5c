// TLV-Link's text feature and the zero-shot prompt matrices, for any TextEncoder.

#include <string>
#include <vector>

#include "tlvlink/text/text_encoder.h"
#include "vector_math.h"

namespace tlvlink::text {

Result<std::vector<float>> text_feature(TextEncoder& encoder, const std::string& key,
                                        const std::string& sentence_desc,
                                        const std::string& phrase_desc) {
  // Both parts come back unit length from every encoder; the sum is deliberately not
  // re-normalised (the paper's y = s/|s| + p/|p|; the loss normalises where it needs to).
  TLV_ASSIGN_OR_RETURN(std::vector<float> s, encoder.embed_sentence(key, sentence_desc));
  TLV_ASSIGN_OR_RETURN(std::vector<float> p, encoder.embed_phrases(key, phrase_desc));
  for (size_t i = 0; i < s.size(); ++i) s[i] += p[i];
  return s;
}

Result<std::vector<float>> zero_shot_matrix(TextEncoder& encoder, const PromptSet& prompts) {
  const auto dim = static_cast<size_t>(encoder.dim());
  std::vector<float> matrix;
  matrix.reserve(prompts.class_names.size() * dim);
  for (size_t c = 0; c < prompts.class_names.size(); ++c) {
    std::vector<float> mean(dim, 0.0f);
    for (const std::string& prompt : prompts.prompts_for(c)) {
      TLV_ASSIGN_OR_RETURN(std::vector<float> e, encoder.embed_prompt(prompt));
      for (size_t i = 0; i < dim; ++i) mean[i] += e[i];
    }
    TLV_TRY(internal::normalise_in_place(mean, prompts.task + " class " + prompts.class_names[c]));
    matrix.insert(matrix.end(), mean.begin(), mean.end());
  }
  return matrix;
}

}  // namespace tlvlink::text
