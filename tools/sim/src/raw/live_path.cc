// LivePath: processed frame -> the camera's raw bytes -> the board's decoder -> processed frame.
#include "tlvlink/sim/live_path.h"

#include <algorithm>

namespace tlvlink::sim {

Result<std::unique_ptr<LivePath>> LivePath::create(const SensorProfile& profile,
                                                   const RawOptions& options) {
  auto path = std::unique_ptr<LivePath>(new LivePath());
  // The sensor seed only shapes render()'s periphery, which encode_frame does not draw.
  TLV_ASSIGN_OR_RETURN(path->camera_, RawCamera::create(profile, /*sensor_seed=*/0, options));
  TLV_ASSIGN_OR_RETURN(path->decoder_, RawDecoder::create(profile));
  return path;
}

Status LivePath::apply(std::span<uint8_t> rgb) {
  TLV_TRY(camera_->encode_frame(rgb, raw_));
  TLV_TRY(decoder_->recover(raw_.bytes, recovered_));
  // Same profile on both sides: the decoder's output has the processed size.
  TLV_ENSURE(recovered_.size() == rgb.size(), ErrorCode::kShapeMismatch,
             "live path: recovered %zu bytes for a %zu-byte frame", recovered_.size(), rgb.size());
  std::copy(recovered_.begin(), recovered_.end(), rgb.begin());
  return {};
}

}  // namespace tlvlink::sim
