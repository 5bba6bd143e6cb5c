#pragma once
// NumPy .npy files (format versions 1.0 and 2.0), the tensor exchange format of the CLI.
// Supported: little-endian '<f4', '|u1', '|i1', '<i4'; C order; rank 0..6. Everything else,
// and every malformed file, is an Error (ErrorCode::kFormat / kIo) naming the file and what is
// wrong; nothing is guessed or truncated.
//
//   auto a = read_npy("frame.npy");          // Result<NpyArray>
//   if (a.ok() && a->dtype == DType::kFloat32) use(a->as<float>());
//   TLV_TRY(write_npy("out.npy", NpyArray::from<float>({1, 128}, values)));

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"

namespace tlvlink::tools {

// Largest array payload read or written (a documented limit, not a truncation).
inline constexpr size_t kMaxNpyDataBytes = size_t{1} << 30;  // 1 GiB
// Largest header accepted (numpy writes < 1 KiB; v2.0 allows 4 GiB, which we refuse).
inline constexpr size_t kMaxNpyHeaderBytes = size_t{1} << 16;
inline constexpr size_t kMaxNpyRank = Shape::kMaxRank;

struct NpyArray {
  DType dtype = DType::kFloat32;
  std::vector<int64_t> shape;   // empty: a 0-d scalar (1 element)
  std::vector<std::byte> data;  // C order, little-endian; size == elements() * dtype_size

  size_t elements() const;
  template <typename T>
  std::span<const T> as() const {
    return {reinterpret_cast<const T*>(data.data()), data.size() / sizeof(T)};
  }
  template <typename T>
  static NpyArray from(std::vector<int64_t> shape, std::span<const T> values);
};

// Parses an in-memory .npy image; `name` (usually the path) prefixes every error.
Result<NpyArray> parse_npy(std::span<const std::byte> bytes, const std::string& name);
Result<NpyArray> read_npy(const std::string& path);

// Serialises as version 1.0 (or 2.0 if the header would not fit 1.0's 16-bit length).
Result<std::vector<std::byte>> encode_npy(const NpyArray& array, int major_version = 1);
Status write_npy(const std::string& path, const NpyArray& array, int major_version = 1);

// A tensor's bytes as an array of its dtype and shape (e.g. an executor's output).
NpyArray npy_from_tensor(const Tensor& tensor, std::span<const std::byte> bytes);

// numpy's descr string for a dtype ("<f4", "|u1", "|i1", "<i4").
const char* npy_descr(DType dtype);

// Shape as "(2, 3)" / "(5,)" / "()" — how numpy prints it; used in error messages.
std::string npy_shape_string(std::span<const int64_t> shape);

template <typename T>
NpyArray NpyArray::from(std::vector<int64_t> shape, std::span<const T> values) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, uint8_t> ||
                std::is_same_v<T, int8_t> || std::is_same_v<T, int32_t>);
  NpyArray a;
  a.dtype = std::is_same_v<T, float>     ? DType::kFloat32
            : std::is_same_v<T, uint8_t> ? DType::kUInt8
            : std::is_same_v<T, int8_t>  ? DType::kInt8
                                         : DType::kInt32;
  a.shape = std::move(shape);
  a.data.resize(values.size_bytes());
  if (!values.empty()) std::memcpy(a.data.data(), values.data(), values.size_bytes());
  return a;
}

}  // namespace tlvlink::tools
