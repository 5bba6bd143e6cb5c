// ONNX TensorProto -> Constant: raw_data or the typed repeated fields, float32/float64 read as
// float, every integer type and bool as int64. Float data must be finite.

#include <cmath>
#include <cstring>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {
namespace {

using DataType = onnx::TensorProto_DataType;

// Bytes per element of a raw_data integer type; 0 for types read elsewhere.
size_t integer_size(int type) {
  switch (type) {
    case onnx::TensorProto_DataType_INT8:
    case onnx::TensorProto_DataType_UINT8:
    case onnx::TensorProto_DataType_BOOL: return 1;
    case onnx::TensorProto_DataType_INT16:
    case onnx::TensorProto_DataType_UINT16: return 2;
    case onnx::TensorProto_DataType_INT32:
    case onnx::TensorProto_DataType_UINT32: return 4;
    case onnx::TensorProto_DataType_INT64:
    case onnx::TensorProto_DataType_UINT64: return 8;
    default: return 0;
  }
}

// One little-endian integer of `type` at p, widened to int64 (uint64 above INT64_MAX wraps;
// such values only appear as "to the end" markers, which stay huge either way).
int64_t read_integer(const char* p, int type) {
  switch (type) {
    case onnx::TensorProto_DataType_INT8: return static_cast<int8_t>(*p);
    case onnx::TensorProto_DataType_UINT8: return static_cast<uint8_t>(*p);
    case onnx::TensorProto_DataType_BOOL: return *p != 0;
    case onnx::TensorProto_DataType_INT16: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case onnx::TensorProto_DataType_UINT16: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case onnx::TensorProto_DataType_INT32: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case onnx::TensorProto_DataType_UINT32: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      int64_t v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
}

Status check_count(size_t have, int64_t want, const std::string& what) {
  TLV_ENSURE(have == static_cast<size_t>(want), ErrorCode::kFormat,
             "%s holds %zu values, its dims need %lld", what.c_str(), have,
             static_cast<long long>(want));
  return {};
}

Status read_floats(const onnx::TensorProto& t, int64_t n, const std::string& what, Constant& c) {
  const bool is_double = t.data_type() == onnx::TensorProto_DataType_DOUBLE;
  c.is_float = true;
  if (t.has_raw_data()) {
    const std::string& raw = t.raw_data();
    const size_t size = is_double ? 8 : 4;
    TLV_TRY(check_count(raw.size() / size, n, what));
    TLV_ENSURE(raw.size() % size == 0, ErrorCode::kFormat, "%s raw data has %zu bytes",
               what.c_str(), raw.size());
    c.f.resize(static_cast<size_t>(n));
    for (size_t k = 0; k < c.f.size(); ++k) {
      if (is_double) {
        double v;
        std::memcpy(&v, raw.data() + k * 8, 8);
        c.f[k] = static_cast<float>(v);
      } else {
        std::memcpy(&c.f[k], raw.data() + k * 4, 4);
      }
    }
  } else if (is_double) {
    TLV_TRY(check_count(static_cast<size_t>(t.double_data_size()), n, what));
    for (double v : t.double_data()) c.f.push_back(static_cast<float>(v));
  } else {
    TLV_TRY(check_count(static_cast<size_t>(t.float_data_size()), n, what));
    c.f.assign(t.float_data().begin(), t.float_data().end());
  }
  for (size_t k = 0; k < c.f.size(); ++k) {
    TLV_ENSURE(std::isfinite(c.f[k]), ErrorCode::kModelInvalidTensor,
               "%s value %zu is %s: the weights are not finite (diverged training or a corrupt "
               "file)",
               what.c_str(), k, std::isnan(c.f[k]) ? "NaN" : "Inf");
  }
  return {};
}

Status read_integers(const onnx::TensorProto& t, int64_t n, const std::string& what, Constant& c) {
  const int type = t.data_type();
  c.is_float = false;
  if (t.has_raw_data()) {
    const std::string& raw = t.raw_data();
    const size_t size = integer_size(type);
    TLV_ENSURE(raw.size() % size == 0, ErrorCode::kFormat, "%s raw data has %zu bytes",
               what.c_str(), raw.size());
    TLV_TRY(check_count(raw.size() / size, n, what));
    c.i.resize(static_cast<size_t>(n));
    for (size_t k = 0; k < c.i.size(); ++k) c.i[k] = read_integer(raw.data() + k * size, type);
  } else if (type == onnx::TensorProto_DataType_INT64) {
    TLV_TRY(check_count(static_cast<size_t>(t.int64_data_size()), n, what));
    c.i.assign(t.int64_data().begin(), t.int64_data().end());
  } else if (type == onnx::TensorProto_DataType_UINT32 ||
             type == onnx::TensorProto_DataType_UINT64) {
    TLV_TRY(check_count(static_cast<size_t>(t.uint64_data_size()), n, what));
    for (uint64_t v : t.uint64_data()) c.i.push_back(static_cast<int64_t>(v));
  } else {
    TLV_TRY(check_count(static_cast<size_t>(t.int32_data_size()), n, what));
    c.i.assign(t.int32_data().begin(), t.int32_data().end());
  }
  return {};
}

}  // namespace

int64_t element_count(std::span<const int64_t> dims) {
  int64_t n = 1;
  for (int64_t d : dims) {
    // Each dimension is bounded on its own too, so a zero elsewhere cannot hide a huge one.
    if (d < 0 || d > kMaxElements || (d > 0 && n > kMaxElements / d)) return -1;
    n *= d;
  }
  return n;
}

std::string dims_string(std::span<const int64_t> dims) {
  std::string s = "[";
  for (size_t k = 0; k < dims.size(); ++k) s += (k ? ", " : "") + std::to_string(dims[k]);
  return s + "]";
}

Result<Constant> read_tensor(const onnx::TensorProto& t, const std::string& what) {
  TLV_ENSURE(t.data_location() != onnx::TensorProto_DataLocation_EXTERNAL,
             ErrorCode::kModelUnsupported,
             "%s keeps its data in an external file; re-export with the weights inside the "
             ".onnx file",
             what.c_str());
  TLV_ENSURE(!t.has_segment(), ErrorCode::kModelUnsupported, "%s is a segmented tensor",
             what.c_str());
  Constant c;
  c.dims.assign(t.dims().begin(), t.dims().end());
  const int64_t n = element_count(c.dims);
  TLV_ENSURE(n >= 0, ErrorCode::kFormat, "%s has invalid or too large dims %s", what.c_str(),
             dims_string(c.dims).c_str());
  const int type = t.data_type();
  if (type == onnx::TensorProto_DataType_FLOAT || type == onnx::TensorProto_DataType_DOUBLE) {
    TLV_TRY(read_floats(t, n, what, c));
  } else if (integer_size(type) != 0) {
    TLV_TRY(read_integers(t, n, what, c));
  } else {
    const std::string name = onnx::TensorProto_DataType_IsValid(type)
                                 ? onnx::TensorProto_DataType_Name(static_cast<DataType>(type))
                                 : std::to_string(type);
    return Error::make(ErrorCode::kModelUnsupported,
                       "%s has data type %s; tlvlink convert reads float32, float64 and integer "
                       "tensors (export float16 models as float32)",
                       what.c_str(), name.c_str());
  }
  return c;
}

template <typename T>
std::vector<T> transpose(std::span<const T> data, std::span<const int64_t> dims,
                         std::span<const int64_t> perm) {
  const size_t rank = dims.size();
  std::vector<int64_t> in_strides(rank, 1), out_dims(rank);
  for (size_t k = rank; k-- > 1;) in_strides[k - 1] = in_strides[k] * dims[k];
  for (size_t k = 0; k < rank; ++k) out_dims[k] = dims[static_cast<size_t>(perm[k])];
  std::vector<T> out(data.size());
  std::vector<int64_t> index(rank, 0);  // multi-index into the output
  for (size_t o = 0; o < out.size(); ++o) {
    int64_t src = 0;
    for (size_t k = 0; k < rank; ++k) src += index[k] * in_strides[static_cast<size_t>(perm[k])];
    out[o] = data[static_cast<size_t>(src)];
    for (size_t k = rank; k-- > 0;) {  // odometer increment
      if (++index[k] < out_dims[k]) break;
      index[k] = 0;
    }
  }
  return out;
}

template std::vector<float> transpose<float>(std::span<const float>, std::span<const int64_t>,
                                             std::span<const int64_t>);
template std::vector<int64_t> transpose<int64_t>(std::span<const int64_t>, std::span<const int64_t>,
                                                 std::span<const int64_t>);

}  // namespace tlvlink::quantize::onnx_internal
