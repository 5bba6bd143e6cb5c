#include "writer_internal.h"

namespace tlvlink::quantize::writer_internal {

std::pair<fb::OpOptions, flatbuffers::Offset<void>> write_options(
    flatbuffers::FlatBufferBuilder& fbb, OpType type, const OpParams& params, size_t input_rank) {
  auto act = [](Activation a) { return static_cast<fb::Activation>(a); };
  if (const auto* p = std::get_if<Conv2DParams>(&params)) {
    auto o = fb::CreateConv2DOptions(fbb, p->kernel_h, p->kernel_w, p->stride_h, p->stride_w,
                                     p->dilation_h, p->dilation_w, p->pad_top, p->pad_bottom,
                                     p->pad_left, p->pad_right, p->groups, act(p->activation));
    return {fb::OpOptions::Conv2DOptions, o.Union()};
  }
  if (const auto* p = std::get_if<FullyConnectedParams>(&params)) {
    return {fb::OpOptions::FullyConnectedOptions,
            fb::CreateFullyConnectedOptions(fbb, act(p->activation)).Union()};
  }
  if (const auto* p = std::get_if<BinaryParams>(&params)) {
    return {fb::OpOptions::BinaryOptions, fb::CreateBinaryOptions(fbb, act(p->activation)).Union()};
  }
  if (const auto* p = std::get_if<ClampParams>(&params)) {
    return {fb::OpOptions::ClampOptions, fb::CreateClampOptions(fbb, p->min, p->max).Union()};
  }
  if (const auto* p = std::get_if<Pool2DParams>(&params)) {
    auto o = fb::CreatePool2DOptions(fbb, p->pool_h, p->pool_w, p->stride_h, p->stride_w,
                                     p->pad_top, p->pad_bottom, p->pad_left, p->pad_right);
    return {fb::OpOptions::Pool2DOptions, o.Union()};
  }
  if (const auto* p = std::get_if<PadParams>(&params)) {
    std::vector<int32_t> before(p->before.begin(),
                                p->before.begin() + static_cast<long>(input_rank));
    std::vector<int32_t> after(p->after.begin(), p->after.begin() + static_cast<long>(input_rank));
    auto o = fb::CreatePadOptions(fbb, fbb.CreateVector(before), fbb.CreateVector(after), p->value);
    return {fb::OpOptions::PadOptions, o.Union()};
  }
  if (const auto* p = std::get_if<ResizeBilinearParams>(&params)) {
    return {fb::OpOptions::ResizeBilinearOptions,
            fb::CreateResizeBilinearOptions(fbb, p->align_corners).Union()};
  }
  if (type == OpType::kReshape) {
    return {fb::OpOptions::ReshapeOptions, fb::CreateReshapeOptions(fbb).Union()};
  }
  return {fb::OpOptions::NONE, 0};
}

}  // namespace tlvlink::quantize::writer_internal
