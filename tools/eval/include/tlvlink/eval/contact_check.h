#pragma once
// The board's contact gate (runtime/pipeline contact_gate.h) on a user's own frames: calibrated
// on their no-contact reference frame(s) — which carry the sensor's colour cast, dust, markers
// and vignetting, so all of that is subtracted — then asked about each frame on its own, as the
// daemon would right after calibrating. Frames are read as the sensor's view (tools/io
// sensor_frame.h), so the blocks and DN are the daemon's.
//
//   auto check = eval::check_contact({"ref.png"}, {"press1.png", "idle2.png"}, {});
//   // check->threshold_dn, check->frames[i].contact, .score_dn

#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/pipeline/contact_gate.h"

namespace tlvlink::eval {

struct ContactCheckOptions {
  std::string sensor;  // a known sensor name, or empty to detect from each frame's size
  pipeline::ContactGateOptions gate;  // reference_frames is set to the number of references
};

struct ContactCheckFrame {
  std::string path;
  bool contact = false;
  float score_dn = 0;  // largest block difference from the reference
};

struct ContactCheck {
  float noise_sigma_dn = 0;  // of a block over the references (0 with one reference)
  float threshold_dn = 0;    // onset: max(min_threshold_dn, noise_multiple x noise)
  std::vector<ContactCheckFrame> frames;
};

// Errors name the file: unreadable, a size no sensor produces, a frame of another size than the
// references, no reference.
Result<ContactCheck> check_contact(const std::vector<std::string>& references,
                                   const std::vector<std::string>& frames,
                                   const ContactCheckOptions& options);

}  // namespace tlvlink::eval
