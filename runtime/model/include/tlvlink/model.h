#pragma once
// Loading a .tlvm model file. The file is untrusted input: load() runs the flatbuffers
// Verifier and every semantic check before it returns a Model; a bad file yields an Error
// naming the tensor / operator / field and the offending value, never a crash.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"
#include "tlvlink/metadata.h"

namespace tlvlink {

inline constexpr uint32_t kSchemaVersion = 1;
// Documented limits; exceeding one is a load error, never a truncation.
// 256 MiB: the shipped int8 encoder is 1.8 MB, an fp32 ResNet-50 ~100 MB; the loader holds two
// copies while loading (file bytes + aligned copy), so this also bounds a board's load peak.
inline constexpr size_t kMaxModelBytes = size_t{256} << 20;
inline constexpr size_t kMaxTensors = 100000;
inline constexpr size_t kMaxOperators = 50000;

struct LoadOptions {
  bool verify_checksum = true;  // recompute the content checksum of the constant buffers
};

// A loaded, validated model. Owns its bytes; Graph and Metadata are views into them.
// Non-copyable (the views point into its own buffer); movable via unique_ptr.
class Model {
 public:
  // Copies `bytes` into a 16-byte-aligned buffer owned by the model, then validates.
  static Result<std::unique_ptr<Model>> load(std::span<const std::byte> bytes,
                                             const LoadOptions& options = {});
  static Result<std::unique_ptr<Model>> load_file(const char* path,
                                                  const LoadOptions& options = {});

  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;

  const Graph& graph() const { return graph_; }
  const Metadata& metadata() const { return metadata_; }
  std::span<const std::byte> bytes() const { return {data_.get(), size_}; }
  uint32_t schema_version() const { return schema_version_; }

 private:
  Model() = default;
  struct AlignedFree { void operator()(std::byte* p) const; };
  std::unique_ptr<std::byte[], AlignedFree> data_;
  size_t size_ = 0;
  uint32_t schema_version_ = 0;
  Graph graph_;
  Metadata metadata_;
};

// FNV-1a 64 over the constant buffers in index order (the value Provenance.content_checksum holds).
uint64_t content_checksum(std::span<const std::span<const std::byte>> buffers);

}  // namespace tlvlink
