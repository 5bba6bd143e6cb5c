// Reading .npy: magic, version, header length, header dict, then a payload whose size must be
// exactly what dtype and shape say.

#include <bit>
#include <cstring>
#include <string_view>

#include "npy_header.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/npy.h"

namespace tlvlink::tools {
namespace {

static_assert(std::endian::native == std::endian::little, "npy I/O assumes a little-endian host");

constexpr char kMagic[] = "\x93NUMPY";
constexpr size_t kMagicSize = 6;

Result<DType> dtype_from_descr(const std::string& descr, const std::string& name) {
  if (descr == "<f4") return DType::kFloat32;
  if (descr == "|u1") return DType::kUInt8;
  if (descr == "|i1") return DType::kInt8;
  if (descr == "<i4") return DType::kInt32;
  return Error::make(ErrorCode::kFormat,
                     "%s: unsupported dtype '%s' (supported: '<f4', '|u1', '|i1', '<i4')",
                     name.c_str(), descr.c_str());
}

uint32_t read_le(const std::byte* p, size_t n) {
  uint32_t v = 0;
  for (size_t i = 0; i < n; ++i) v |= static_cast<uint32_t>(p[i]) << (8 * i);
  return v;
}

}  // namespace

size_t NpyArray::elements() const {
  size_t n = 1;
  for (int64_t d : shape) n *= static_cast<size_t>(d);
  return n;
}

Result<NpyArray> parse_npy(std::span<const std::byte> bytes, const std::string& name) {
  TLV_ENSURE(bytes.size() >= kMagicSize + 2 && std::memcmp(bytes.data(), kMagic, kMagicSize) == 0,
             ErrorCode::kFormat, "%s: not a .npy file (bad magic; expected \\x93NUMPY)",
             name.c_str());
  const auto major = static_cast<int>(bytes[6]);
  const auto minor = static_cast<int>(bytes[7]);
  TLV_ENSURE((major == 1 || major == 2) && minor == 0, ErrorCode::kFormat,
             "%s: .npy format version %d.%d is not supported (1.0 or 2.0)", name.c_str(), major,
             minor);
  const size_t len_size = major == 1 ? 2 : 4;
  const size_t prefix = kMagicSize + 2 + len_size;
  TLV_ENSURE(bytes.size() >= prefix, ErrorCode::kFormat, "%s: truncated .npy header (%zu bytes)",
             name.c_str(), bytes.size());
  const size_t header_len = read_le(bytes.data() + kMagicSize + 2, len_size);
  TLV_ENSURE(header_len <= kMaxNpyHeaderBytes, ErrorCode::kFormat,
             "%s: header length %zu exceeds the %zu-byte limit", name.c_str(), header_len,
             kMaxNpyHeaderBytes);
  TLV_ENSURE(header_len <= bytes.size() - prefix, ErrorCode::kFormat,
             "%s: header length %zu runs past the end of the file (%zu bytes)", name.c_str(),
             header_len, bytes.size());
  const std::string_view text(reinterpret_cast<const char*>(bytes.data() + prefix), header_len);
  for (char c : text) {
    TLV_ENSURE(c >= 0x20 || c == '\n' || c == '\t' || c == '\r', ErrorCode::kFormat,
               "%s: header contains a non-ASCII or control byte", name.c_str());
  }
  TLV_ASSIGN_OR_RETURN(NpyHeader h, parse_npy_header_dict(text, name));
  TLV_ENSURE(!h.fortran_order, ErrorCode::kFormat,
             "%s: fortran_order is True; only C-order arrays are supported "
             "(save with np.ascontiguousarray)",
             name.c_str());

  NpyArray a;
  TLV_ASSIGN_OR_RETURN(a.dtype, dtype_from_descr(h.descr, name));
  a.shape = std::move(h.shape);
  size_t expected = dtype_size(a.dtype);
  for (size_t i = 0; i < a.shape.size(); ++i) {
    const auto d = static_cast<size_t>(a.shape[i]);
    TLV_ENSURE(d >= 1, ErrorCode::kFormat,
               "%s: shape %s has an empty dimension %zu (not supported)", name.c_str(),
               npy_shape_string(a.shape).c_str(), i);
    TLV_ENSURE(expected <= kMaxNpyDataBytes / d, ErrorCode::kFormat,
               "%s: shape %s of %s needs more than the %zu-byte limit", name.c_str(),
               npy_shape_string(a.shape).c_str(), h.descr.c_str(), kMaxNpyDataBytes);
    expected *= d;
  }
  const size_t available = bytes.size() - prefix - header_len;
  TLV_ENSURE(available == expected, ErrorCode::kFormat,
             "%s: data is %zu bytes, shape %s of %s needs %zu (%s)", name.c_str(), available,
             npy_shape_string(a.shape).c_str(), h.descr.c_str(), expected,
             available < expected ? "truncated" : "trailing bytes");
  const std::byte* data = bytes.data() + prefix + header_len;
  a.data.assign(data, data + expected);
  return a;
}

Result<NpyArray> read_npy(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes,
                       read_file(path, kMaxNpyDataBytes + kMaxNpyHeaderBytes + 16));
  return parse_npy(bytes, path);
}

}  // namespace tlvlink::tools
