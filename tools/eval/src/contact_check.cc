// The board's contact gate on a user's frames (contact_check.h).

#include "tlvlink/eval/contact_check.h"

#include <optional>

#include "tlvlink/io/sensor_frame.h"

namespace tlvlink::eval {
namespace {

Result<image::Image> read_view(const std::string& path, const std::string& sensor) {
  TLV_ASSIGN_OR_RETURN(tools::SensorFrame f, tools::sensor_frame_from_file(path, sensor));
  return std::move(f.view);
}

}  // namespace

Result<ContactCheck> check_contact(const std::vector<std::string>& references,
                                   const std::vector<std::string>& frames,
                                   const ContactCheckOptions& options) {
  TLV_ENSURE(!references.empty(), ErrorCode::kInvalidArgument,
             "contact: no reference frame (a frame of the gel with nothing touching it)");
  pipeline::ContactGateOptions gate_options = options.gate;
  gate_options.reference_frames = static_cast<int32_t>(references.size());
  std::optional<pipeline::ContactGate> calibrated;
  int32_t width = 0, height = 0;
  for (const std::string& r : references) {
    TLV_ASSIGN_OR_RETURN(image::Image view, read_view(r, options.sensor));
    if (!calibrated) {
      width = view.width;
      height = view.height;
      TLV_ASSIGN_OR_RETURN(
          pipeline::ContactGate g,
          pipeline::ContactGate::create(width, height, view.channels, gate_options));
      calibrated.emplace(std::move(g));
    }
    auto d = calibrated->update(view.view());
    if (!d.ok()) return d.error().with_context("%s", r.c_str());
  }
  ContactCheck check;
  check.noise_sigma_dn = calibrated->noise_sigma_dn();
  check.threshold_dn = calibrated->threshold_dn();
  for (const std::string& f : frames) {
    TLV_ASSIGN_OR_RETURN(image::Image view, read_view(f, options.sensor));
    TLV_ENSURE(view.width == width && view.height == height, ErrorCode::kShapeMismatch,
               "%s: a %dx%d view, the references' is %dx%d", f.c_str(), view.width, view.height,
               width, height);
    pipeline::ContactGate gate = *calibrated;  // each frame on its own, right after calibration
    auto d = gate.update(view.view());
    if (!d.ok()) return d.error().with_context("%s", f.c_str());
    check.frames.push_back({f, d->state == pipeline::ContactState::kContact, d->score_dn});
  }
  return check;
}

}  // namespace tlvlink::eval
