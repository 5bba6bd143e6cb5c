#include "tlvlink/io/npy_image.h"

namespace tlvlink::tools {

Result<Image> image_from_npy(const NpyArray& a, const std::string& name) {
  TLV_ENSURE(a.dtype == DType::kUInt8, ErrorCode::kShapeMismatch,
             "%s: image tensors must be uint8, is %s", name.c_str(), npy_descr(a.dtype));
  const bool batched = a.shape.size() == 4;
  TLV_ENSURE((a.shape.size() == 3 || (batched && a.shape[0] == 1)), ErrorCode::kShapeMismatch,
             "%s: uint8 image shape %s; expected [H,W,C] or [1,H,W,C]", name.c_str(),
             npy_shape_string(a.shape).c_str());
  const size_t o = batched ? 1 : 0;
  const int64_t h = a.shape[o], w = a.shape[o + 1], c = a.shape[o + 2];
  TLV_ENSURE((c == 1 || c == 3) && h <= kMaxImageSideForNpy && w <= kMaxImageSideForNpy,
             ErrorCode::kShapeMismatch,
             "%s: uint8 image shape %s; need 1 or 3 channels and sides <= %d", name.c_str(),
             npy_shape_string(a.shape).c_str(), kMaxImageSideForNpy);
  Image img{static_cast<int32_t>(w), static_cast<int32_t>(h), static_cast<int32_t>(c), {}};
  const auto* p = reinterpret_cast<const uint8_t*>(a.data.data());
  img.pixels.assign(p, p + a.data.size());
  return img;
}

}  // namespace tlvlink::tools
