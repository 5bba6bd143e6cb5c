// The only file that calls XNNPACK's subgraph API (Debian snapshot 0.0~git20220216).
#include "xnnpack/xnn_api.h"

#include <vector>

#include <pthreadpool.h>
#include <xnnpack.h>

#include "xnnpack/status.h"

namespace tlvlink::xnn {

static_assert(kInvalidValueId == XNN_INVALID_VALUE_ID);
static_assert(kExtraBytes == XNN_EXTRA_BYTES);

namespace {

// Turns a status into Status, naming the call and the node.
Status check(xnn_status status, const char* call, const NodeRef& who) {
  if (status == xnn_status_success) return Status();
  return backend_error(status, call, who);
}
#define TLV_XNN_CALL(who, fn, ...) check(fn(__VA_ARGS__), #fn, (who))

xnn_datatype to_datatype(ValueType type) {
  switch (type) {
    case ValueType::kFloat32: return xnn_datatype_fp32;
    case ValueType::kQInt8: return xnn_datatype_qint8;
    case ValueType::kQInt32: return xnn_datatype_qint32;
    case ValueType::kQCInt8: return xnn_datatype_qcint8;
    case ValueType::kQCInt32: return xnn_datatype_qcint32;
  }
  return xnn_datatype_invalid;
}

}  // namespace

Status initialize() {
  // A function-local static is initialized exactly once, even with concurrent first callers.
  static const xnn_status status = xnn_initialize(/*allocator=*/nullptr);
  return check(status, "xnn_initialize", NodeRef{"runtime", {}, -1});
}

// ---- Subgraph ----

void Subgraph::Deleter::operator()(xnn_subgraph* s) const { xnn_delete_subgraph(s); }

Result<Subgraph> Subgraph::create(uint32_t external_value_ids) {
  xnn_subgraph_t subgraph = nullptr;
  TLV_TRY(TLV_XNN_CALL((NodeRef{"runtime", {}, -1}), xnn_create_subgraph, external_value_ids,
                       /*flags=*/0, &subgraph));
  return Subgraph(subgraph);
}

Result<uint32_t> Subgraph::define_value(const ValueDesc& d, const NodeRef& who) {
  uint32_t flags = 0;
  if (d.external_input) flags |= XNN_VALUE_FLAG_EXTERNAL_INPUT;
  if (d.external_output) flags |= XNN_VALUE_FLAG_EXTERNAL_OUTPUT;
  const xnn_datatype type = to_datatype(d.type);
  uint32_t id = XNN_INVALID_VALUE_ID;
  switch (d.type) {
    case ValueType::kFloat32:
      TLV_TRY(TLV_XNN_CALL(who, xnn_define_tensor_value, get(), type, d.dims.size(), d.dims.data(),
                           d.data, d.external_id, flags, &id));
      break;
    case ValueType::kQInt8:
    case ValueType::kQInt32:
      TLV_TRY(TLV_XNN_CALL(who, xnn_define_quantized_tensor_value, get(), type, d.zero_point,
                           d.scale, d.dims.size(), d.dims.data(), d.data, d.external_id, flags,
                           &id));
      break;
    case ValueType::kQCInt8:
    case ValueType::kQCInt32:
      TLV_TRY(TLV_XNN_CALL(who, xnn_define_channelwise_quantized_tensor_value, get(), type,
                           d.channel_scales.data(), d.dims.size(), d.channel_dim, d.dims.data(),
                           d.data, d.external_id, flags, &id));
      break;
  }
  return id;
}

Status Subgraph::define_convolution_2d(const Conv2DSpec& s, const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_convolution_2d, get(), s.pad_top, s.pad_right, s.pad_bottom,
                      s.pad_left, s.kernel_h, s.kernel_w, s.stride_h, s.stride_w, s.dilation_h,
                      s.dilation_w, s.groups, s.group_input_channels, s.group_output_channels,
                      s.output_min, s.output_max, s.input, s.filter, s.bias, s.output, /*flags=*/0);
}

Status Subgraph::define_depthwise_convolution_2d(const Conv2DSpec& s, const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_depthwise_convolution_2d, get(), s.pad_top, s.pad_right,
                      s.pad_bottom, s.pad_left, s.kernel_h, s.kernel_w, s.stride_h, s.stride_w,
                      s.dilation_h, s.dilation_w, s.depth_multiplier, s.group_input_channels,
                      s.output_min, s.output_max, s.input, s.filter, s.bias, s.output,
                      /*flags=*/0);
}

Status Subgraph::define_fully_connected(float output_min, float output_max, uint32_t input,
                                        uint32_t filter, uint32_t bias, uint32_t output,
                                        const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_fully_connected, get(), output_min, output_max, input, filter,
                      bias, output, /*flags=*/0);
}

Status Subgraph::define_binary(BinaryKind kind, float output_min, float output_max, uint32_t input1,
                               uint32_t input2, uint32_t output, const NodeRef& who) {
  if (kind == BinaryKind::kAdd) {
    return TLV_XNN_CALL(who, xnn_define_add2, get(), output_min, output_max, input1, input2, output,
                        /*flags=*/0);
  }
  return TLV_XNN_CALL(who, xnn_define_multiply2, get(), output_min, output_max, input1, input2,
                      output, /*flags=*/0);
}

Status Subgraph::define_clamp(float output_min, float output_max, uint32_t input, uint32_t output,
                              const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_clamp, get(), output_min, output_max, input, output,
                      /*flags=*/0);
}

Status Subgraph::define_sigmoid(uint32_t input, uint32_t output, const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_sigmoid, get(), input, output, /*flags=*/0);
}

Status Subgraph::define_convert(uint32_t input, uint32_t output, const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_convert, get(), input, output, /*flags=*/0);
}

Status Subgraph::define_constant_pad(std::span<const size_t> before, std::span<const size_t> after,
                                     float value, uint32_t input, uint32_t output,
                                     const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_static_constant_pad, get(), before.data(), after.data(),
                      value, input, output, /*flags=*/0);
}

Status Subgraph::define_reshape(std::span<const size_t> new_shape, uint32_t input, uint32_t output,
                                const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_static_reshape, get(), new_shape.size(), new_shape.data(),
                      input, output, /*flags=*/0);
}

Status Subgraph::define_resize_bilinear_2d(size_t new_height, size_t new_width, bool align_corners,
                                           uint32_t input, uint32_t output, const NodeRef& who) {
  // Without flags this XNNPACK uses half-pixel centres, our schema's default.
  const uint32_t flags = align_corners ? XNN_FLAG_ALIGN_CORNERS : 0;
  return TLV_XNN_CALL(who, xnn_define_static_resize_bilinear_2d, get(), new_height, new_width,
                      input, output, flags);
}

Status Subgraph::define_global_average_pooling_2d(float output_min, float output_max,
                                                  uint32_t input, uint32_t output,
                                                  const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_global_average_pooling_2d, get(), output_min, output_max,
                      input, output, /*flags=*/0);
}

Status Subgraph::define_max_pooling_2d(const MaxPool2DSpec& s, const NodeRef& who) {
  return TLV_XNN_CALL(who, xnn_define_max_pooling_2d, get(), s.pad_top, s.pad_right, s.pad_bottom,
                      s.pad_left, s.pool_h, s.pool_w, s.stride_h, s.stride_w,
                      /*dilation_height=*/1, /*dilation_width=*/1, s.output_min, s.output_max,
                      s.input, s.output, /*flags=*/0);
}

// ---- ThreadPool ----

void ThreadPool::Deleter::operator()(pthreadpool* p) const { pthreadpool_destroy(p); }

Result<ThreadPool> ThreadPool::create(int threads) {
  TLV_ENSURE(threads >= 1, ErrorCode::kInvalidArgument, "executor threads must be >= 1 (got %d)",
             threads);
  if (threads == 1) return ThreadPool(nullptr);
  pthreadpool_t pool = pthreadpool_create(static_cast<size_t>(threads));
  TLV_ENSURE(pool != nullptr, ErrorCode::kOutOfMemory, "pthreadpool_create(%d) failed", threads);
  return ThreadPool(pool);
}

// ---- Runtime ----

void Runtime::Deleter::operator()(xnn_runtime* r) const { xnn_delete_runtime(r); }

Result<Runtime> Runtime::create(const Subgraph& subgraph, const ThreadPool& pool,
                                const NodeRef& who) {
  xnn_runtime_t runtime = nullptr;
  TLV_TRY(
      TLV_XNN_CALL(who, xnn_create_runtime_v2, subgraph.get(), pool.get(), /*flags=*/0, &runtime));
  return Runtime(runtime);
}

Status Runtime::setup(std::span<const ExternalBinding> externals) {
  // Setup happens once at creation, so this small copy is not in the per-frame path.
  std::vector<xnn_external_value> values;
  values.reserve(externals.size());
  for (const ExternalBinding& e : externals) values.push_back(xnn_external_value{e.id, e.data});
  return TLV_XNN_CALL((NodeRef{"runtime", {}, -1}), xnn_setup_runtime, handle_.get(), values.size(),
                      values.data());
}

Status Runtime::invoke() {
  return TLV_XNN_CALL((NodeRef{"runtime", {}, -1}), xnn_invoke_runtime, handle_.get());
}

}  // namespace tlvlink::xnn
