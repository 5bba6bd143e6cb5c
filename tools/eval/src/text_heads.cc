// Zero-shot heads through tools/text, with the text encoder the model records (or the user's).

#include <nlohmann/json.hpp>
#include <string>

#include "tlvlink/eval/heads.h"
#include "tlvlink/text/text_encoder.h"

namespace tlvlink::eval {
namespace {

std::string join(const std::vector<std::string>& parts, const char* sep) {
  std::string s;
  for (const std::string& p : parts) s += (s.empty() ? "" : sep) + p;
  return s;
}

// The encoder named by the options, else by the model's provenance, else the default hashing one.
Result<std::unique_ptr<text::TextEncoder>> encoder_for(const Metadata& m, const TextOptions& o) {
  if (!o.precomputed_dir.empty()) return text::open_precomputed_text_embeddings(o.precomputed_dir);
  int32_t dim = m.embedding_dim;
  uint64_t seed = o.hashing_seed.value_or(kDefaultHashingSeed);
  if (!o.hashing_seed) {
    const nlohmann::json j =
        nlohmann::json::parse(m.provenance.training, nullptr, /*allow_exceptions=*/false);
    if (!j.is_discarded() && j.is_object() && j.contains("text_encoder") &&
        j["text_encoder"].is_object()) {
      const nlohmann::json& t = j["text_encoder"];
      if (t.contains("embeddings_dir") && t["embeddings_dir"].is_string() &&
          !t["embeddings_dir"].get<std::string>().empty()) {
        return text::open_precomputed_text_embeddings(t["embeddings_dir"].get<std::string>());
      }
      if (t.contains("seed") && t["seed"].is_number_unsigned()) seed = t["seed"].get<uint64_t>();
      if (t.contains("dim") && t["dim"].is_number_integer()) dim = t["dim"].get<int32_t>();
    }
  }
  return text::make_hashing_text_encoder({.dim = dim, .seed = seed});
}

}  // namespace

Result<TextHeads> zero_shot_heads_from_text(const Metadata& metadata, const TextOptions& text) {
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<text::TextEncoder> enc, encoder_for(metadata, text));
  TLV_ENSURE(enc->dim() == metadata.embedding_dim, ErrorCode::kInvalidArgument,
             "text encoder %s has dim %d, the model's embedding dim is %d",
             enc->description().c_str(), enc->dim(), metadata.embedding_dim);
  TextHeads out;
  out.encoder = enc->description();
  for (const text::PromptSet& p : {text::material_prompts(), text::hardness_prompts(),
                                   text::roughness_prompts(), text::grasp_prompts()}) {
    quantize::ZeroShotHeadSpec h;
    h.name = p.task;
    h.class_names = p.class_names;
    h.prompt_template =
        p.templates.empty() ? join(p.fixed_prompts, " | ") : join(p.templates, " | ");
    auto matrix = text::zero_shot_matrix(*enc, p);
    if (!matrix.ok()) return matrix.error().with_context("zero-shot head '%s'", p.task.c_str());
    h.prompt_matrix = std::move(matrix).value();
    h.logit_scale = kZeroShotLogitScale;
    out.heads.push_back(std::move(h));
  }
  return out;
}

}  // namespace tlvlink::eval
