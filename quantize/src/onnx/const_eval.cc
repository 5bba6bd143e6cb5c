// Constant folding of the shape arithmetic exporters leave in graphs: torch's Pad pads
// (ConstantOfShape/Concat/Slice/Transpose/Cast), x.view(x.size(0), -1) (Shape/Gather/
// Unsqueeze/Concat), Constant nodes. Evaluated once at import; none of it reaches the model.

#include <algorithm>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {
namespace {

constexpr std::string_view kEvaluable[] = {
    "Constant", "ConstantOfShape", "Identity", "Shape",   "Gather", "Unsqueeze",
    "Squeeze",  "Concat",          "Reshape",  "Flatten", "Slice",  "Transpose",
    "Cast",     "Expand",          "Add",      "Sub",     "Mul",    "Div"};

// ConstantOfShape builds shape-arithmetic helpers, never weights: a bigger fill is refused
// rather than allocated.
constexpr int64_t kMaxFilledElements = int64_t{1} << 24;

std::vector<int64_t> strides_of(std::span<const int64_t> dims) {
  std::vector<int64_t> s(dims.size(), 1);
  for (size_t k = dims.size(); k-- > 1;) s[k - 1] = s[k] * dims[k];
  return s;
}

// Calls fn(multi_index) for every element of `dims` in row-major order.
template <typename Fn>
void for_each_index(std::span<const int64_t> dims, Fn&& fn) {
  const int64_t n = element_count(dims);
  const std::vector<int64_t> strides = strides_of(dims);
  std::vector<int64_t> index(dims.size());
  for (int64_t e = 0; e < n; ++e) {
    for (size_t k = 0; k < dims.size(); ++k) index[k] = (e / strides[k]) % dims[k];
    fn(index);
  }
}

Constant gather(const Constant& src, std::vector<int64_t> dims, std::span<const int64_t> index) {
  Constant out;
  out.dims = std::move(dims);
  out.is_float = src.is_float;
  for (int64_t k : index) {
    if (src.is_float) {
      out.f.push_back(src.f[static_cast<size_t>(k)]);
    } else {
      out.i.push_back(src.i[static_cast<size_t>(k)]);
    }
  }
  return out;
}

Constant as_float(Constant c) {
  if (!c.is_float) {
    c.f.assign(c.i.begin(), c.i.end());
    c.i.clear();
    c.is_float = true;
  }
  return c;
}

Result<int64_t> normalise_axis(const onnx::NodeProto& node, int64_t axis, size_t rank) {
  const auto r = static_cast<int64_t>(rank);
  if (axis < 0) axis += r;
  TLV_ENSURE(axis >= 0 && axis < r, ErrorCode::kModelInvalidOperator, "%s: axis out of range",
             node_label(node).c_str());
  return axis;
}

// Integer list from an attribute (older opsets) or a constant input (newer ones).
Result<std::vector<int64_t>> ints_from(Importer& imp, const onnx::NodeProto& node, const char* attr,
                                       int input, int64_t since_opset) {
  if (imp.opset() < since_opset) return attr_ints(node, attr);
  if (!imp.has_input(node, input)) return std::vector<int64_t>{};
  TLV_ASSIGN_OR_RETURN(const Constant* c, imp.constant_input(node, input));
  std::vector<int64_t> v;
  for (size_t k = 0; k < c->elements(); ++k) v.push_back(c->int_at(k));
  return v;
}

Result<Constant> eval_constant(const onnx::NodeProto& node) {
  const std::string what = node_label(node);
  for (const onnx::AttributeProto& a : node.attribute()) {
    Constant c;
    if (a.name() == "value") return read_tensor(a.t(), what);
    if (a.name() == "value_float") {
      c.f = {a.f()};
    } else if (a.name() == "value_floats") {
      c.f.assign(a.floats().begin(), a.floats().end());
      c.dims = {static_cast<int64_t>(c.f.size())};
    } else if (a.name() == "value_int") {
      c.is_float = false;
      c.i = {a.i()};
    } else if (a.name() == "value_ints") {
      c.is_float = false;
      c.i.assign(a.ints().begin(), a.ints().end());
      c.dims = {static_cast<int64_t>(c.i.size())};
    } else {
      continue;
    }
    return c;
  }
  return node_error(ErrorCode::kModelUnsupported, node,
                    "only tensor, float(s) and int(s) values are supported");
}

Result<Constant> eval_shape(Importer& imp, const onnx::NodeProto& node) {
  std::vector<int64_t> dims;
  if (imp.is_constant(node.input(0))) {
    TLV_ASSIGN_OR_RETURN(const Constant* c, imp.constant_input(node, 0));
    dims = c->dims;
  } else {
    TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
    dims = imp.value(x).shape;
  }
  const auto rank = static_cast<int64_t>(dims.size());
  TLV_ASSIGN_OR_RETURN(int64_t start, attr_int(node, "start", 0));
  TLV_ASSIGN_OR_RETURN(int64_t end, attr_int(node, "end", rank));
  if (start < 0) start += rank;
  if (end < 0) end += rank;
  start = std::clamp<int64_t>(start, 0, rank);
  end = std::clamp<int64_t>(end, start, rank);
  Constant c;
  c.is_float = false;
  c.i.assign(dims.begin() + start, dims.begin() + end);
  c.dims = {static_cast<int64_t>(c.i.size())};
  return c;
}

Result<Constant> eval_gather(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const Constant* data, imp.constant_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const Constant* indices, imp.constant_input(node, 1));
  TLV_ASSIGN_OR_RETURN(int64_t axis, attr_int(node, "axis", 0));
  TLV_ASSIGN_OR_RETURN(axis, normalise_axis(node, axis, data->dims.size()));
  const auto a = static_cast<size_t>(axis);
  const int64_t axis_dim = data->dims[a];
  const int64_t outer = element_count(std::span(data->dims).first(a));
  const int64_t inner = element_count(std::span(data->dims).subspan(a + 1));
  std::vector<int64_t> dims(data->dims.begin(), data->dims.begin() + axis);
  dims.insert(dims.end(), indices->dims.begin(), indices->dims.end());
  dims.insert(dims.end(), data->dims.begin() + axis + 1, data->dims.end());
  std::vector<int64_t> index;
  for (int64_t o = 0; o < outer; ++o) {
    for (size_t k = 0; k < indices->elements(); ++k) {
      int64_t idx = indices->int_at(k);
      if (idx < 0) idx += axis_dim;
      TLV_ENSURE(idx >= 0 && idx < axis_dim, ErrorCode::kModelInvalidOperator,
                 "%s: index %lld out of range", node_label(node).c_str(),
                 static_cast<long long>(indices->int_at(k)));
      for (int64_t i = 0; i < inner; ++i) index.push_back((o * axis_dim + idx) * inner + i);
    }
  }
  return gather(*data, std::move(dims), index);
}

Result<Constant> eval_unsqueeze_squeeze(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const Constant* data, imp.constant_input(node, 0));
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> axes, ints_from(imp, node, "axes", 1, 13));
  Constant out = *data;
  if (node.op_type() == "Unsqueeze") {
    const size_t rank = data->dims.size() + axes.size();
    for (int64_t& a : axes) {
      TLV_ASSIGN_OR_RETURN(a, normalise_axis(node, a, rank));
    }
    std::sort(axes.begin(), axes.end());
    for (int64_t a : axes) out.dims.insert(out.dims.begin() + a, 1);
    return out;
  }
  out.dims.clear();
  for (size_t k = 0; k < data->dims.size(); ++k) {
    bool drop = axes.empty() && data->dims[k] == 1;
    for (int64_t a : axes) {
      TLV_ASSIGN_OR_RETURN(const int64_t n, normalise_axis(node, a, data->dims.size()));
      drop = drop || n == static_cast<int64_t>(k);
    }
    if (!drop) out.dims.push_back(data->dims[k]);
  }
  return out;
}

Result<Constant> eval_concat(Importer& imp, const onnx::NodeProto& node) {
  std::vector<Constant> parts;
  bool any_float = false;
  for (int k = 0; k < node.input_size(); ++k) {
    TLV_ASSIGN_OR_RETURN(const Constant* c, imp.constant_input(node, k));
    parts.push_back(*c);
    any_float = any_float || c->is_float;
  }
  TLV_ENSURE(!parts.empty(), ErrorCode::kFormat, "%s has no inputs", node_label(node).c_str());
  TLV_ASSIGN_OR_RETURN(int64_t axis, attr_int(node, "axis", 0));
  TLV_ASSIGN_OR_RETURN(axis, normalise_axis(node, axis, parts[0].dims.size()));
  const auto a = static_cast<size_t>(axis);
  Constant out;
  out.is_float = any_float;
  out.dims = parts[0].dims;
  out.dims[a] = 0;
  for (Constant& p : parts) {
    if (any_float) p = as_float(std::move(p));
    bool same = p.dims.size() == out.dims.size();
    for (size_t k = 0; same && k < p.dims.size(); ++k) same = k == a || p.dims[k] == out.dims[k];
    TLV_ENSURE(same, ErrorCode::kModelInvalidOperator, "%s: inputs %s and %s do not concatenate",
               node_label(node).c_str(), dims_string(parts[0].dims).c_str(),
               dims_string(p.dims).c_str());
    out.dims[a] += p.dims[a];
  }
  const int64_t outer = element_count(std::span(out.dims).first(a));
  for (int64_t o = 0; o < outer; ++o) {
    for (const Constant& p : parts) {
      const int64_t block = element_count(std::span(p.dims).subspan(a));
      const auto begin = static_cast<size_t>(o * block), end = static_cast<size_t>((o + 1) * block);
      if (any_float) {
        out.f.insert(out.f.end(), p.f.begin() + begin, p.f.begin() + end);
      } else {
        out.i.insert(out.i.end(), p.i.begin() + begin, p.i.begin() + end);
      }
    }
  }
  return out;
}

Result<Constant> eval_slice(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const Constant* data, imp.constant_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const std::vector<int64_t> starts, ints_from(imp, node, "starts", 1, 10));
  TLV_ASSIGN_OR_RETURN(const std::vector<int64_t> ends, ints_from(imp, node, "ends", 2, 10));
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> axes, ints_from(imp, node, "axes", 3, 10));
  std::vector<int64_t> steps;
  if (imp.opset() >= 10) {
    TLV_ASSIGN_OR_RETURN(steps, ints_from(imp, node, "steps", 4, 10));
  }
  const size_t rank = data->dims.size();
  if (axes.empty()) {
    for (size_t k = 0; k < starts.size(); ++k) axes.push_back(static_cast<int64_t>(k));
  }
  if (steps.empty()) steps.assign(starts.size(), 1);
  TLV_ENSURE(
      ends.size() == starts.size() && axes.size() == starts.size() && steps.size() == starts.size(),
      ErrorCode::kModelInvalidOperator, "%s: starts/ends/axes/steps differ in length",
      node_label(node).c_str());
  std::vector<int64_t> first(rank, 0), step(rank, 1), dims = data->dims;
  for (size_t k = 0; k < starts.size(); ++k) {
    TLV_ASSIGN_OR_RETURN(const int64_t ax, normalise_axis(node, axes[k], rank));
    const auto a = static_cast<size_t>(ax);
    const int64_t d = data->dims[a];
    TLV_ENSURE(steps[k] != 0, ErrorCode::kModelInvalidOperator, "%s: step 0",
               node_label(node).c_str());
    int64_t s = starts[k] < 0 ? std::max<int64_t>(starts[k], -d) + d : starts[k];
    int64_t e = ends[k] < 0 ? std::max<int64_t>(ends[k], -d - 1) + d : ends[k];
    if (steps[k] > 0) {
      s = std::clamp<int64_t>(s, 0, d);
      e = std::clamp<int64_t>(e, 0, d);
      dims[a] = e > s ? (e - s + steps[k] - 1) / steps[k] : 0;
    } else {
      s = std::clamp<int64_t>(s, 0, d - 1);
      e = std::clamp<int64_t>(e, -1, d - 1);
      dims[a] = s > e ? (s - e - steps[k] - 1) / -steps[k] : 0;
    }
    first[a] = s;
    step[a] = steps[k];
  }
  const std::vector<int64_t> strides = strides_of(data->dims);
  std::vector<int64_t> index;
  for_each_index(dims, [&](const std::vector<int64_t>& i) {
    int64_t src = 0;
    for (size_t k = 0; k < rank; ++k) src += (first[k] + i[k] * step[k]) * strides[k];
    index.push_back(src);
  });
  return gather(*data, dims, index);
}

Result<Constant> eval_cast(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const Constant* data, imp.constant_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const int64_t to, attr_int(node, "to", 0));
  if (to == onnx::TensorProto_DataType_FLOAT || to == onnx::TensorProto_DataType_DOUBLE) {
    return as_float(*data);
  }
  TLV_ENSURE(to != onnx::TensorProto_DataType_STRING && to != onnx::TensorProto_DataType_FLOAT16 &&
                 to != onnx::TensorProto_DataType_BFLOAT16 && to >= 1 && to <= 13,
             ErrorCode::kModelUnsupported, "%s: cast to type %lld is not supported",
             node_label(node).c_str(), static_cast<long long>(to));
  Constant out;
  out.dims = data->dims;
  out.is_float = false;
  for (size_t k = 0; k < data->elements(); ++k) {
    const int64_t v = data->int_at(k);  // floats truncate toward zero
    out.i.push_back(to == onnx::TensorProto_DataType_BOOL ? (v != 0 || data->float_at(k) != 0.0f)
                                                          : v);
  }
  return out;
}

// Element index of `in` (broadcast against `out`) for every element of `out`.
std::vector<int64_t> broadcast_index(std::span<const int64_t> out, std::span<const int64_t> in) {
  std::vector<int64_t> s(out.size(), 0);
  const std::vector<int64_t> own = strides_of(in);
  const size_t lead = out.size() - in.size();
  for (size_t k = 0; k < in.size(); ++k) s[lead + k] = in[k] == 1 ? 0 : own[k];
  std::vector<int64_t> index;
  for_each_index(out, [&](const std::vector<int64_t>& i) {
    int64_t src = 0;
    for (size_t k = 0; k < out.size(); ++k) src += i[k] * s[k];
    index.push_back(src);
  });
  return index;
}

Result<Constant> eval_expand(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const Constant* data, imp.constant_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const Constant* shape, imp.constant_input(node, 1));
  TLV_ENSURE(!shape->is_float && shape->dims.size() == 1, ErrorCode::kModelInvalidOperator,
             "%s: the shape must be a 1-D int64 tensor", node_label(node).c_str());
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> dims, broadcast_dims(node, data->dims, shape->i));
  TLV_ENSURE(element_count(dims) >= 0 && element_count(dims) <= kMaxFilledElements,
             ErrorCode::kModelUnsupported, "%s: shape %s is too large", node_label(node).c_str(),
             dims_string(dims).c_str());
  const std::vector<int64_t> index = broadcast_index(dims, data->dims);
  return gather(*data, std::move(dims), index);
}

Result<Constant> eval_arithmetic(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const Constant* pa, imp.constant_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const Constant* pb, imp.constant_input(node, 1));
  const bool is_float = pa->is_float || pb->is_float;
  const Constant a = is_float ? as_float(*pa) : *pa, b = is_float ? as_float(*pb) : *pb;
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> dims, broadcast_dims(node, a.dims, b.dims));
  TLV_ENSURE(element_count(dims) >= 0 && element_count(dims) <= kMaxFilledElements,
             ErrorCode::kModelUnsupported, "%s: result %s is too large", node_label(node).c_str(),
             dims_string(dims).c_str());
  const char op = node.op_type()[0];  // A, S, M, D
  const std::vector<int64_t> ia = broadcast_index(dims, a.dims), ib = broadcast_index(dims, b.dims);
  Constant out;
  out.dims = dims;
  out.is_float = is_float;
  for (size_t e = 0; e < ia.size(); ++e) {
    const auto j = static_cast<size_t>(ia[e]), k = static_cast<size_t>(ib[e]);
    if (is_float) {
      const float x = a.f[j], y = b.f[k];
      out.f.push_back(op == 'A' ? x + y : op == 'S' ? x - y : op == 'M' ? x * y : x / y);
    } else {
      const int64_t x = a.i[j], y = b.i[k];
      TLV_ENSURE(op != 'D' || y != 0, ErrorCode::kModelInvalidOperator,
                 "%s: integer division by zero", node_label(node).c_str());
      out.i.push_back(op == 'A' ? x + y : op == 'S' ? x - y : op == 'M' ? x * y : x / y);
    }
  }
  return out;
}

}  // namespace

bool const_evaluable(std::string_view op_type) {
  return std::find(std::begin(kEvaluable), std::end(kEvaluable), op_type) != std::end(kEvaluable);
}

Result<Constant> evaluate_constant(Importer& imp, const onnx::NodeProto& node) {
  const std::string& op = node.op_type();
  if (op == "Constant") return eval_constant(node);
  if (op == "Shape") return eval_shape(imp, node);
  if (op == "Gather") return eval_gather(imp, node);
  if (op == "Unsqueeze" || op == "Squeeze") return eval_unsqueeze_squeeze(imp, node);
  if (op == "Concat") return eval_concat(imp, node);
  if (op == "Slice") return eval_slice(imp, node);
  if (op == "Cast") return eval_cast(imp, node);
  if (op == "Expand") return eval_expand(imp, node);
  if (op == "Add" || op == "Sub" || op == "Mul" || op == "Div") return eval_arithmetic(imp, node);

  TLV_ASSIGN_OR_RETURN(const Constant* data, imp.constant_input(node, 0));
  if (op == "Identity") return *data;
  if (op == "ConstantOfShape") {
    TLV_ENSURE(!data->is_float && data->dims.size() == 1, ErrorCode::kModelInvalidOperator,
               "%s: the shape must be a 1-D int64 tensor", node_label(node).c_str());
    const int64_t n = element_count(data->i);
    TLV_ENSURE(n >= 0 && n <= kMaxFilledElements, ErrorCode::kModelUnsupported,
               "%s: shape %s is invalid or too large", node_label(node).c_str(),
               dims_string(data->i).c_str());
    Constant fill;
    if (const onnx::AttributeProto* a = find_attribute(node, "value"); a != nullptr) {
      TLV_ASSIGN_OR_RETURN(fill, read_tensor(a->t(), node_label(node)));
    } else {
      fill.f = {0.0f};
    }
    TLV_ENSURE(fill.elements() == 1, ErrorCode::kModelInvalidOperator,
               "%s: value must have one element", node_label(node).c_str());
    return gather(fill, data->i, std::vector<int64_t>(static_cast<size_t>(n), 0));
  }
  if (op == "Reshape") {
    TLV_ASSIGN_OR_RETURN(const Constant* shape, imp.constant_input(node, 1));
    TLV_ASSIGN_OR_RETURN(const int64_t allowzero, attr_int(node, "allowzero", 0));
    Constant out = *data;
    TLV_ASSIGN_OR_RETURN(out.dims, reshape_target(node, data->dims, *shape, allowzero != 0));
    return out;
  }
  if (op == "Flatten") {
    TLV_ASSIGN_OR_RETURN(int64_t axis, attr_int(node, "axis", 1));
    const auto rank = static_cast<int64_t>(data->dims.size());
    if (axis < 0) axis += rank;
    TLV_ENSURE(axis >= 0 && axis <= rank, ErrorCode::kModelInvalidOperator, "%s: bad axis",
               node_label(node).c_str());
    Constant out = *data;
    out.dims = {element_count(std::span(data->dims).first(static_cast<size_t>(axis))),
                element_count(std::span(data->dims).subspan(static_cast<size_t>(axis)))};
    return out;
  }
  // Transpose
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> perm, attr_ints(node, "perm"));
  const size_t rank = data->dims.size();
  if (perm.empty()) {
    for (size_t k = rank; k-- > 0;) perm.push_back(static_cast<int64_t>(k));
  }
  std::vector<bool> seen(rank, false);
  for (int64_t p : perm) {
    TLV_ENSURE(perm.size() == rank && p >= 0 && p < static_cast<int64_t>(rank) &&
                   !seen[static_cast<size_t>(p)],
               ErrorCode::kModelInvalidOperator, "%s: perm %s is not a permutation",
               node_label(node).c_str(), dims_string(perm).c_str());
    seen[static_cast<size_t>(p)] = true;
  }
  Constant out;
  out.is_float = data->is_float;
  for (int64_t p : perm) out.dims.push_back(data->dims[static_cast<size_t>(p)]);
  if (data->is_float) {
    out.f = transpose<float>(data->f, data->dims, perm);
  } else {
    out.i = transpose<int64_t>(data->i, data->dims, perm);
  }
  return out;
}

}  // namespace tlvlink::quantize::onnx_internal
