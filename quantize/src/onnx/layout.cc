// NCHW -> NHWC bookkeeping and the shape arithmetic shared by the converters: broadcasting,
// Reshape targets, Conv/MaxPool windows (auto_pad), constants moved into an activation's layout.

#include <algorithm>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {

std::vector<int32_t> stored_shape(const Value& v) {
  std::vector<int32_t> s;
  for (int64_t d : v.shape) s.push_back(static_cast<int32_t>(d));
  if (v.layout == Layout::kNhwc) s = {s[0], s[2], s[3], s[1]};
  return s;
}

bool memory_is_logical(const Value& v) {
  switch (v.layout) {
    case Layout::kPlain: return true;
    case Layout::kNhwc: return v.shape[1] == 1 || v.shape[2] * v.shape[3] == 1;
    case Layout::kPermuted:
      for (size_t j = 0; j < v.perm.size(); ++j) {
        if (v.perm[j] != static_cast<int64_t>(j)) return false;
      }
      return true;
  }
  return false;
}

Result<std::vector<int64_t>> broadcast_dims(const onnx::NodeProto& node, std::span<const int64_t> a,
                                            std::span<const int64_t> b) {
  const size_t rank = std::max(a.size(), b.size());
  std::vector<int64_t> out(rank);
  for (size_t k = 0; k < rank; ++k) {
    const int64_t da = k < rank - a.size() ? 1 : a[k - (rank - a.size())];
    const int64_t db = k < rank - b.size() ? 1 : b[k - (rank - b.size())];
    if (da != db && da != 1 && db != 1) {
      return node_error(ErrorCode::kModelInvalidOperator, node, "cannot broadcast %s with %s",
                        dims_string(a).c_str(), dims_string(b).c_str());
    }
    out[k] = da == 1 ? db : da;
  }
  return out;
}

Result<std::vector<int64_t>> reshape_target(const onnx::NodeProto& node,
                                            std::span<const int64_t> in, const Constant& shape,
                                            bool allowzero) {
  TLV_ENSURE(!shape.is_float && shape.dims.size() == 1, ErrorCode::kModelInvalidOperator,
             "%s: the shape must be a 1-D int64 tensor", node_label(node).c_str());
  std::vector<int64_t> out = shape.i;
  int inferred = -1;
  int64_t known = 1;
  for (size_t k = 0; k < out.size(); ++k) {
    if (out[k] == 0 && !allowzero) {
      TLV_ENSURE(k < in.size(), ErrorCode::kModelInvalidOperator,
                 "%s: shape entry %zu copies a dimension the input %s lacks",
                 node_label(node).c_str(), k, dims_string(in).c_str());
      out[k] = in[k];
    }
    if (out[k] == -1) {
      TLV_ENSURE(inferred < 0, ErrorCode::kModelInvalidOperator, "%s: two -1 entries in %s",
                 node_label(node).c_str(), dims_string(shape.i).c_str());
      inferred = static_cast<int>(k);
      continue;
    }
    TLV_ENSURE(out[k] >= 1 && out[k] <= kMaxElements, ErrorCode::kModelUnsupported,
               "%s: shape %s has an empty or negative dimension", node_label(node).c_str(),
               dims_string(shape.i).c_str());
    known *= out[k];
    TLV_ENSURE(known <= kMaxElements, ErrorCode::kModelUnsupported, "%s: shape %s is too large",
               node_label(node).c_str(), dims_string(shape.i).c_str());
  }
  const int64_t total = element_count(in);
  if (inferred >= 0) {
    TLV_ENSURE(total % known == 0, ErrorCode::kModelInvalidOperator, "%s cannot reshape %s to %s",
               node_label(node).c_str(), dims_string(in).c_str(), dims_string(shape.i).c_str());
    out[static_cast<size_t>(inferred)] = total / known;
    known = total;
  }
  TLV_ENSURE(known == total, ErrorCode::kModelInvalidOperator, "%s cannot reshape %s to %s",
             node_label(node).c_str(), dims_string(in).c_str(), dims_string(shape.i).c_str());
  return out;
}

Result<int64_t> window_output(const onnx::NodeProto& node, int64_t in, Window& w,
                              std::string_view auto_pad) {
  const int64_t effective = (w.kernel - 1) * w.dilation + 1;
  if (auto_pad == "SAME_UPPER" || auto_pad == "SAME_LOWER") {
    const int64_t out = (in + w.stride - 1) / w.stride;
    const int64_t total = std::max<int64_t>(0, (out - 1) * w.stride + effective - in);
    // SAME_UPPER puts the odd extra pixel at the end, SAME_LOWER at the beginning.
    w.pad_begin = auto_pad == "SAME_UPPER" ? total / 2 : total - total / 2;
    w.pad_end = total - w.pad_begin;
  } else if (auto_pad == "VALID") {
    w.pad_begin = w.pad_end = 0;
  } else if (auto_pad != "NOTSET" && !auto_pad.empty()) {
    return node_error(ErrorCode::kModelUnsupported, node, "auto_pad '%.*s' is unknown",
                      static_cast<int>(auto_pad.size()), auto_pad.data());
  }
  const int64_t padded = in + w.pad_begin + w.pad_end;
  TLV_ENSURE(padded >= effective, ErrorCode::kModelInvalidOperator,
             "%s: the window (%lld with dilation) is larger than the padded input (%lld)",
             node_label(node).c_str(), static_cast<long long>(effective),
             static_cast<long long>(padded));
  return (padded - effective) / w.stride + 1;
}

Result<Windows> read_windows(const onnx::NodeProto& node, std::span<const int64_t> kernel,
                             std::string* auto_pad) {
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> strides, attr_ints(node, "strides"));
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> dilations, attr_ints(node, "dilations"));
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> pads, attr_ints(node, "pads"));
  TLV_ASSIGN_OR_RETURN(*auto_pad, attr_string(node, "auto_pad", "NOTSET"));
  if (strides.empty()) strides = {1, 1};
  if (dilations.empty()) dilations = {1, 1};
  if (pads.empty()) pads = {0, 0, 0, 0};
  TLV_ENSURE(kernel.size() == 2 && strides.size() == 2 && dilations.size() == 2 && pads.size() == 4,
             ErrorCode::kModelUnsupported,
             "%s: only 2-D windows are supported (kernel %s, strides %s, pads %s)",
             node_label(node).c_str(), dims_string(kernel).c_str(), dims_string(strides).c_str(),
             dims_string(pads).c_str());
  Windows w;
  for (size_t k = 0; k < 2; ++k) {
    w[k] = Window{kernel[k], strides[k], dilations[k], pads[k], pads[k + 2]};
    TLV_ENSURE(w[k].kernel >= 1 && w[k].stride >= 1 && w[k].dilation >= 1 && w[k].kernel <= 1024 &&
                   w[k].stride <= 1024 && w[k].dilation <= 1024,
               ErrorCode::kModelUnsupported, "%s: kernel %s, strides %s, dilations %s invalid",
               node_label(node).c_str(), dims_string(kernel).c_str(), dims_string(strides).c_str(),
               dims_string(dilations).c_str());
    TLV_ENSURE(
        w[k].pad_begin >= 0 && w[k].pad_end >= 0 && w[k].pad_begin <= 1024 && w[k].pad_end <= 1024,
        ErrorCode::kModelUnsupported, "%s: pads %s are negative or too large",
        node_label(node).c_str(), dims_string(pads).c_str());
  }
  return w;
}

Result<ConstOperand> constant_for(const onnx::NodeProto& node, const Value& act, const Constant& c,
                                  std::string name) {
  ConstOperand out;
  out.name = std::move(name);
  std::vector<float> data(c.elements());
  for (size_t k = 0; k < data.size(); ++k) data[k] = c.float_at(k);
  switch (act.layout) {
    case Layout::kNhwc: {
      TLV_ENSURE(c.dims.size() <= 4, ErrorCode::kModelUnsupported,
                 "%s: constant %s has a higher rank than the feature map", node_label(node).c_str(),
                 dims_string(c.dims).c_str());
      std::vector<int64_t> d(4 - c.dims.size(), 1);
      d.insert(d.end(), c.dims.begin(), c.dims.end());
      TLV_ENSURE(d[0] == 1, ErrorCode::kModelUnsupported, "%s: constant %s would enlarge the batch",
                 node_label(node).c_str(), dims_string(c.dims).c_str());
      const int64_t to_nhwc[4] = {0, 2, 3, 1};
      out.data = transpose<float>(data, d, to_nhwc);
      out.shape = {static_cast<int32_t>(d[0]), static_cast<int32_t>(d[2]),
                   static_cast<int32_t>(d[3]), static_cast<int32_t>(d[1])};
      return out;
    }
    case Layout::kPlain:
      TLV_ENSURE(c.dims.size() <= act.shape.size(), ErrorCode::kModelUnsupported,
                 "%s: constant %s has a higher rank than the activation %s",
                 node_label(node).c_str(), dims_string(c.dims).c_str(),
                 dims_string(act.shape).c_str());
      break;
    case Layout::kPermuted: {
      const int64_t features = act.shape[1];
      const bool scalar = data.size() == 1;
      const bool row = c.dims.size() <= 2 && !c.dims.empty() && c.dims.back() == features &&
                       static_cast<int64_t>(data.size()) == features;
      TLV_ENSURE(scalar || row, ErrorCode::kModelUnsupported,
                 "%s: constant %s against a flattened NCHW feature map", node_label(node).c_str(),
                 dims_string(c.dims).c_str());
      if (row) {
        for (size_t j = 0; j < data.size(); ++j) {
          data[j] = c.float_at(static_cast<size_t>(act.perm[j]));
        }
      }
      break;
    }
  }
  for (int64_t d : c.dims) out.shape.push_back(static_cast<int32_t>(d));
  if (out.shape.empty()) out.shape = {1};  // a scalar broadcasts as [1]
  out.data = std::move(data);
  return out;
}

std::vector<float> per_channel(const ConstOperand& c, const Value& act) {
  const std::vector<int32_t> s = stored_shape(act);
  if (c.shape.size() > s.size()) return {};
  for (size_t k = 0; k + 1 < c.shape.size(); ++k) {
    if (c.shape[k] != 1) return {};
  }
  const int32_t channels = s.back();
  const int32_t last = c.shape.empty() ? 1 : c.shape.back();
  if (last != channels && last != 1) return {};
  std::vector<float> v(static_cast<size_t>(channels));
  for (size_t k = 0; k < v.size(); ++k) v[k] = c.data[last == 1 ? 0 : k];
  return v;
}

}  // namespace tlvlink::quantize::onnx_internal
