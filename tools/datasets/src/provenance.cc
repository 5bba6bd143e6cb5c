#include "provenance.h"

#include <cmath>
#include <string_view>

#include "tlvlink/io/file.h"

namespace tlvlink::datasets {

Status validate(const WriterOptions& options) {
  TLV_ENSURE(options.jpeg_quality >= 1 && options.jpeg_quality <= 100, ErrorCode::kInvalidArgument,
             "jpeg_quality %d outside 1..100", options.jpeg_quality);
  TLV_ENSURE(std::isfinite(options.test_fraction) && options.test_fraction >= 0 &&
                 options.test_fraction <= 1,
             ErrorCode::kInvalidArgument, "test_fraction %g outside [0, 1]", options.test_fraction);
  Json j;
  std::string why;
  TLV_ENSURE(parse_json(options.generator_json, j, why) && j.is_object(),
             ErrorCode::kInvalidArgument, "generator_json is not a JSON object: %s",
             why.empty() ? "another JSON type" : why.c_str());
  return {};
}

Status write_provenance(const std::string& dir, const char* format, const WriterOptions& options,
                        const OrderedJson& writer_extra, WriteSummary& summary) {
  OrderedJson writer = {{"jpeg_quality", options.jpeg_quality},
                        {"jpeg_chroma", options.jpeg_full_chroma ? "4:4:4" : "4:2:0"},
                        {"test_fraction", options.test_fraction},
                        {"sidecar", options.sidecar}};
  for (const auto& [k, v] : writer_extra.items()) writer[k] = v;
  const std::string path = join_path(dir, kProvenanceFile);
  OrderedJson j = {{"format", format},
                   {"written_by", "tlvlink_datasets"},
                   {"generator", OrderedJson::parse(options.generator_json)},
                   {"writer", std::move(writer)},
                   {"counts",
                    {{"items", summary.items},
                     {"train_items", summary.train_items},
                     {"test_items", summary.test_items},
                     {"objects", summary.objects},
                     {"test_objects", summary.test_objects}}}};
  const std::string text = j.dump(2) + "\n";
  TLV_TRY(tools::write_file(path, std::as_bytes(std::span<const char>(text.data(), text.size()))));
  summary.files += 1;
  summary.bytes += static_cast<int64_t>(text.size());
  return {};
}

}  // namespace tlvlink::datasets
