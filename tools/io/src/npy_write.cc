// Writing .npy: the header is padded with spaces and a newline so the data starts on a
// 64-byte boundary (what numpy >= 1.14 writes).

#include <limits>

#include "npy_header.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/npy.h"

namespace tlvlink::tools {
namespace {
constexpr size_t kAlign = 64;
}  // namespace

NpyArray npy_from_tensor(const Tensor& t, std::span<const std::byte> bytes) {
  NpyArray a;
  a.dtype = t.dtype;
  a.shape.assign(t.shape.dims.begin(),
                 t.shape.dims.begin() + static_cast<std::ptrdiff_t>(t.shape.rank));
  a.data.assign(bytes.begin(), bytes.end());
  return a;
}

const char* npy_descr(DType dtype) {
  switch (dtype) {
    case DType::kFloat32: return "<f4";
    case DType::kUInt8: return "|u1";
    case DType::kInt8: return "|i1";
    case DType::kInt32: return "<i4";
  }
  return "?";
}

std::string npy_shape_string(std::span<const int64_t> shape) {
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(shape[i]);
  }
  if (shape.size() == 1) s += ",";
  return s + ")";
}

Result<std::vector<std::byte>> encode_npy(const NpyArray& a, int major_version) {
  TLV_ENSURE(major_version == 1 || major_version == 2, ErrorCode::kInvalidArgument,
             "npy version %d.0 cannot be written (1 or 2)", major_version);
  TLV_ENSURE(a.shape.size() <= kMaxNpyRank, ErrorCode::kInvalidArgument,
             "npy: rank %zu exceeds %zu", a.shape.size(), kMaxNpyRank);
  size_t expected = dtype_size(a.dtype);
  for (int64_t d : a.shape) {
    TLV_ENSURE(d >= 1 && expected <= kMaxNpyDataBytes / static_cast<size_t>(d),
               ErrorCode::kInvalidArgument, "npy: shape %s is empty or exceeds the %zu-byte limit",
               npy_shape_string(a.shape).c_str(), kMaxNpyDataBytes);
    expected *= static_cast<size_t>(d);
  }
  TLV_ENSURE(a.data.size() == expected, ErrorCode::kInvalidArgument,
             "npy: %zu data bytes for shape %s of %s (needs %zu)", a.data.size(),
             npy_shape_string(a.shape).c_str(), npy_descr(a.dtype), expected);

  std::string header = format_npy_header_dict(a.dtype, a.shape);
  int version = major_version;
  size_t prefix = 6 + 2 + (version == 1 ? 2 : 4);
  size_t total = (prefix + header.size() + 1 + kAlign - 1) / kAlign * kAlign;
  if (version == 1 && total - prefix > std::numeric_limits<uint16_t>::max()) {
    version = 2;  // the header does not fit 1.0's 16-bit length
    prefix = 12;
    total = (prefix + header.size() + 1 + kAlign - 1) / kAlign * kAlign;
  }
  header.append(total - prefix - header.size() - 1, ' ');
  header.push_back('\n');

  std::vector<std::byte> out;
  out.reserve(total + a.data.size());
  for (char c : std::string_view("\x93NUMPY", 6)) out.push_back(static_cast<std::byte>(c));
  out.push_back(static_cast<std::byte>(version));
  out.push_back(std::byte{0});
  const size_t len = header.size();
  for (size_t i = 0; i < prefix - 8; ++i)
    out.push_back(static_cast<std::byte>((len >> (8 * i)) & 0xff));
  for (char c : header) out.push_back(static_cast<std::byte>(c));
  out.insert(out.end(), a.data.begin(), a.data.end());
  return out;
}

Status write_npy(const std::string& path, const NpyArray& array, int major_version) {
  auto bytes = encode_npy(array, major_version);
  if (!bytes.ok()) return bytes.error().with_context("%s", path.c_str());
  return write_file(path, *bytes);
}

}  // namespace tlvlink::tools
