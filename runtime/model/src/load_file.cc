// Model::load_file: a model from a path, checked before it is read. Only a regular file is
// opened (a FIFO would block, /dev/zero never ends); its size is checked against
// kMaxModelBytes from fstat and its identifier from the first 8 bytes, so a file that is not a
// model costs 8 bytes of reading, never its size in memory.

#include <vector>

#include "model_internal.h"
#include "tlvlink/model.h"
#include "tlvlink/regular_file.h"

namespace tlvlink {

namespace {

// A flatbuffer starts with its root table's offset (4 bytes) then the file identifier.
constexpr size_t kHeadBytes = 8;

}  // namespace

namespace model_internal {

Status check_identifier(const uint8_t* raw) {
  if (fb::ModelBufferHasIdentifier(raw)) return {};
  char id[5] = {};
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>(raw[4 + i]);
    id[i] = (c >= 32 && c < 127) ? c : '?';
  }
  return Error::make(ErrorCode::kModelMalformed,
                     "not a tlvlink model: file identifier is '%s', expected '%s'", id,
                     fb::ModelIdentifier());
}

}  // namespace model_internal

Result<std::unique_ptr<Model>> Model::load_file(const char* path, const LoadOptions& options) {
  TLV_ASSIGN_OR_RETURN(const RegularFile f, RegularFile::open(path));
  TLV_ENSURE(f.size() <= kMaxModelBytes, ErrorCode::kModelMalformed,
             "%s: model file is %llu bytes, over the %zu-byte limit (kMaxModelBytes)", path,
             static_cast<unsigned long long>(f.size()), kMaxModelBytes);
  TLV_ENSURE(f.size() >= kHeadBytes, ErrorCode::kModelMalformed,
             "%s: not a tlvlink model: %llu bytes, shorter than a flatbuffer header", path,
             static_cast<unsigned long long>(f.size()));
  std::byte head[kHeadBytes];
  TLV_TRY(f.read_at(head, 0, path));
  Status id = model_internal::check_identifier(reinterpret_cast<const uint8_t*>(head));
  if (!id.ok()) return id.error().with_context("%s", path);
  const uint32_t root = flatbuffers::ReadScalar<uint32_t>(head);
  TLV_ENSURE(root >= kHeadBytes && root < f.size(), ErrorCode::kModelMalformed,
             "%s: root table offset %u outside the %llu-byte file", path, root,
             static_cast<unsigned long long>(f.size()));
  // Straight into the model's own aligned buffer: one copy of the file in memory.
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> model, with_buffer(static_cast<size_t>(f.size())));
  TLV_TRY(f.read_at({model->data_.get(), model->size_}, 0, path));
  auto result = parse(std::move(model), options);
  if (!result.ok()) return result.error().with_context("%s", path);
  return result;
}

}  // namespace tlvlink
