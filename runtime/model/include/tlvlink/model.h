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
#include "tlvlink/model_integrity.h"

namespace tlvlink {

inline constexpr uint32_t kSchemaVersion = 1;
// Documented limits; exceeding one is a load error, never a truncation.
// 256 MiB: the shipped int8 encoder is 0.8 MB, an fp32 ResNet-50 ~100 MB. load_file() reads the
// file straight into the model's aligned buffer (one copy), so this also bounds a board's load
// peak; load() from memory adds the caller's bytes.
inline constexpr size_t kMaxModelBytes = size_t{256} << 20;
inline constexpr size_t kMaxTensors = 100000;
inline constexpr size_t kMaxOperators = 50000;

struct LoadOptions {
  // Recompute the file's BLAKE2b-256 hash and compare it with the trailer's (model_integrity.h).
  // Off only for fuzzing and tests: the trailer is then stripped if present, and a file without
  // one is read whole.
  bool verify_checksum = true;
  // When set, the file must be signed by this key (kModelSignature otherwise). Borrowed for the
  // call.
  const PublicKey* public_key = nullptr;
  // Accept a file written before the integrity trailer if its legacy FNV-1a checksum of the
  // constant buffers matches: only for `tlvlink upgrade`, which rewrites it with a trailer.
  bool accept_legacy = false;
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
  // The whole file as loaded (flatbuffer, then the trailer if it has one).
  std::span<const std::byte> bytes() const { return {data_.get(), size_}; }
  uint32_t schema_version() const { return schema_version_; }
  // The checked trailer; body_size == bytes().size() and hash all zero for a legacy file
  // (accept_legacy) or one loaded without a trailer and verify_checksum off.
  const ModelIntegrity& integrity() const { return integrity_; }

 private:
  Model() = default;
  // load() and load_file() share these: an aligned buffer for `size` bytes (zero-padded), then
  // the checks and parsing of what was put into it, in place.
  static Result<std::unique_ptr<Model>> with_buffer(size_t size);
  static Result<std::unique_ptr<Model>> parse(std::unique_ptr<Model> model,
                                              const LoadOptions& options);
  struct AlignedFree {
    void operator()(std::byte* p) const;
  };
  std::unique_ptr<std::byte[], AlignedFree> data_;
  size_t size_ = 0;
  uint32_t schema_version_ = 0;
  ModelIntegrity integrity_;
  Graph graph_;
  Metadata metadata_;
};

// FNV-1a 64 over the constant buffers in index order (the value Provenance.content_checksum
// holds). Legacy: superseded by the trailer's hash, checked only for files without one
// (LoadOptions::accept_legacy); still written so runtimes from before the trailer read new files.
uint64_t content_checksum(std::span<const std::span<const std::byte>> buffers);

}  // namespace tlvlink
