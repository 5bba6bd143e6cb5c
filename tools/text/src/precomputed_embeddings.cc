// Text embeddings computed elsewhere (any frozen text model), read from the layout documented in
// text_encoder.h and looked up by sample key or prompt text.

#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

#include "tlvlink/io/line_reader.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/text/text_encoder.h"
#include "vector_math.h"

namespace tlvlink::text {
namespace {

struct Table {
  std::string path;
  int64_t rows = 0, dim = 0;
  std::vector<float> values;  // rows x dim, each row unit length
};

Result<std::vector<std::string>> read_lines(const std::string& path) {
  tools::LineReader in;
  TLV_TRY(in.open(path));
  std::vector<std::string> lines;
  std::string line;
  while (in.next(line)) {
    TLV_ENSURE(!in.too_long(), ErrorCode::kFormat, "%s:%lld: line longer than %zu bytes",
               path.c_str(), static_cast<long long>(in.line_number()), tools::kMaxLineBytes);
    lines.push_back(line);
  }
  TLV_TRY(in.error());
  return lines;
}

Result<Table> read_table(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(tools::NpyArray a, tools::read_npy(path));
  if (a.dtype != DType::kFloat32 || a.shape.size() != 2) {
    return Error::make(ErrorCode::kFormat, "%s: expected a float32 [N, D] array, got %s %s",
                       path.c_str(), tools::npy_descr(a.dtype),
                       tools::npy_shape_string(a.shape).c_str());
  }
  Table t{path, a.shape[0], a.shape[1], {}};
  if (t.dim < kMinTextDim || t.dim > kMaxTextDim) {
    return Error::make(ErrorCode::kFormat, "%s: embedding dim %lld outside %d..%d", path.c_str(),
                       static_cast<long long>(t.dim), kMinTextDim, kMaxTextDim);
  }
  const auto values = a.as<float>();
  t.values.assign(values.begin(), values.end());
  for (int64_t r = 0; r < t.rows; ++r) {
    std::span<float> row(t.values.data() + r * t.dim, static_cast<size_t>(t.dim));
    TLV_TRY(internal::normalise_in_place(row, path + " row " + std::to_string(r)));
  }
  return t;
}

// Maps each line of `lines_path` to its row; duplicates and count mismatches are errors.
Result<std::unordered_map<std::string, int64_t>> index_lines(const std::string& lines_path,
                                                             int64_t rows,
                                                             const std::string& table_path) {
  TLV_ASSIGN_OR_RETURN(std::vector<std::string> lines, read_lines(lines_path));
  if (static_cast<int64_t>(lines.size()) != rows) {
    return Error::make(ErrorCode::kFormat, "%s has %zu lines but %s has %lld rows",
                       lines_path.c_str(), lines.size(), table_path.c_str(),
                       static_cast<long long>(rows));
  }
  std::unordered_map<std::string, int64_t> index;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (!index.emplace(lines[i], static_cast<int64_t>(i)).second) {
      return Error::make(ErrorCode::kFormat, "%s:%zu: duplicate entry \"%.80s\"",
                         lines_path.c_str(), i + 1, lines[i].c_str());
    }
  }
  return index;
}

class PrecomputedTextEmbeddings final : public TextEncoder {
 public:
  PrecomputedTextEmbeddings(std::string dir, Table sentence, Table phrase, Table prompts,
                            std::unordered_map<std::string, int64_t> keys,
                            std::unordered_map<std::string, int64_t> prompt_rows)
      : dir_(std::move(dir)),
        sentence_(std::move(sentence)),
        phrase_(std::move(phrase)),
        prompts_(std::move(prompts)),
        keys_(std::move(keys)),
        prompt_rows_(std::move(prompt_rows)) {}

  int32_t dim() const override { return static_cast<int32_t>(sentence_.dim); }
  std::string description() const override { return "precomputed(" + dir_ + ")"; }
  Result<std::vector<float>> embed_sentence(const std::string& key, const std::string&) override {
    return lookup(sentence_, keys_, key, "sample key");
  }
  Result<std::vector<float>> embed_phrases(const std::string& key, const std::string&) override {
    return lookup(phrase_, keys_, key, "sample key");
  }
  Result<std::vector<float>> embed_prompt(const std::string& prompt) override {
    return lookup(prompts_, prompt_rows_, prompt, "prompt");
  }

 private:
  static Result<std::vector<float>> lookup(const Table& t,
                                           const std::unordered_map<std::string, int64_t>& index,
                                           const std::string& name, const char* what) {
    const auto it = index.find(name);
    if (it == index.end()) {
      return Error::make(ErrorCode::kInvalidArgument, "%s: no embedding for %s \"%.100s\"",
                         t.path.c_str(), what, name.c_str());
    }
    const float* row = t.values.data() + it->second * t.dim;
    return std::vector<float>(row, row + t.dim);
  }

  std::string dir_;
  Table sentence_, phrase_, prompts_;
  std::unordered_map<std::string, int64_t> keys_, prompt_rows_;
};

}  // namespace

Result<std::unique_ptr<TextEncoder>> open_precomputed_text_embeddings(const std::string& dir) {
  TLV_ASSIGN_OR_RETURN(Table sentence, read_table(dir + "/sentence.npy"));
  TLV_ASSIGN_OR_RETURN(Table phrase, read_table(dir + "/phrase.npy"));
  TLV_ASSIGN_OR_RETURN(Table prompts, read_table(dir + "/prompts.npy"));
  for (const Table* t : {&phrase, &prompts}) {
    if (t->dim != sentence.dim) {
      return Error::make(ErrorCode::kFormat, "%s: dim %lld differs from sentence.npy's %lld",
                         t->path.c_str(), static_cast<long long>(t->dim),
                         static_cast<long long>(sentence.dim));
    }
  }
  if (phrase.rows != sentence.rows) {
    return Error::make(ErrorCode::kFormat, "%s: %lld rows but sentence.npy has %lld",
                       phrase.path.c_str(), static_cast<long long>(phrase.rows),
                       static_cast<long long>(sentence.rows));
  }
  TLV_ASSIGN_OR_RETURN(auto keys, index_lines(dir + "/keys.txt", sentence.rows, sentence.path));
  TLV_ASSIGN_OR_RETURN(auto prompt_rows,
                       index_lines(dir + "/prompts.txt", prompts.rows, prompts.path));
  return std::unique_ptr<TextEncoder>(
      new PrecomputedTextEmbeddings(dir, std::move(sentence), std::move(phrase), std::move(prompts),
                                    std::move(keys), std::move(prompt_rows)));
}

}  // namespace tlvlink::text
