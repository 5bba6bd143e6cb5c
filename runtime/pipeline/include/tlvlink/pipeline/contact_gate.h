#pragma once
// Contact gating: is anything touching the gel? A no-contact reference is averaged over the first
// frames after start (and after every re-zero); each frame's difference from it decides contact,
// and the encoder is skipped while nothing touches. A missed contact costs a prediction, a false
// one only an inference, so the threshold sits well below a light touch: a multiple of the
// reference's own frame-to-frame noise, measured while it was averaged.
//
// The test is cheap: the frame is reduced to block means on a coarse grid (per channel), and the
// score is the largest |block - reference block| in 8-bit DN. Block means of ~100 pixels cut the
// camera noise ~10x while a 2 mm imprint still covers whole blocks. While idle, the reference
// follows slow drift (LED warm-up, temperature) with an exponential average; it never learns
// during contact. Made once (allocates); update() allocates nothing.

#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/image/image.h"

namespace tlvlink::pipeline {

struct ContactGateOptions {
  int32_t reference_frames = 20;              // frames averaged into the reference, [1, 1000]
  int32_t grid_width = 32, grid_height = 24;  // blocks the frame is reduced to, [1, 256]
  float noise_multiple = 8.0f;    // contact when the score exceeds this many noise sigmas...
  float min_threshold_dn = 4.0f;  // ...and at least this many DN (a noiseless reference)
  float release_fraction = 0.6f;  // contact ends below release_fraction x the threshold...
  int32_t release_frames = 2;     // ...for this many consecutive frames (hysteresis)
  float drift_rate = 0.02f;       // per idle frame, weight of the frame in the reference
};
Status validate(const ContactGateOptions& options);

enum class ContactState : uint8_t {
  kCalibrating = 0,  // averaging the reference (the gate says "contact": never skip unknowingly)
  kNoContact = 1,
  kContact = 2,
};
const char* contact_state_name(ContactState state);  // "calibrating", "none", "contact"

struct ContactDecision {
  ContactState state = ContactState::kCalibrating;
  float score_dn = 0;      // largest block difference from the reference
  float threshold_dn = 0;  // the current onset threshold (0 while calibrating)
  bool onset = false;      // contact began with this frame
  bool release = false;    // contact ended with this frame
};

class ContactGate {
 public:
  // For frames of width x height x channels (1 or 3).
  static Result<ContactGate> create(int32_t width, int32_t height, int32_t channels,
                                    const ContactGateOptions& options);

  // One frame (the sensor's processed frame). Frames of another size are a kShapeMismatch.
  Result<ContactDecision> update(const image::ImageView& frame);
  // Starts averaging a new reference (the re-zero command): nothing must touch the gel now.
  void rezero();

  // The last frame's per-cell view of the decision, 1 bit per grid cell (row-major, LSB first):
  // a cell is 1 when its block mean differs from the reference by more than the onset threshold
  // in any channel; all 0 while calibrating. `bits` must hold (cells + 7) / 8 bytes
  // (kInvalidArgument otherwise). No allocation: the FrameImage's contact mask.
  Status contact_mask(std::span<uint8_t> bits) const;
  int32_t grid_width() const { return options_.grid_width; }
  int32_t grid_height() const { return options_.grid_height; }

  float noise_sigma_dn() const { return noise_sigma_; }  // of a block, measured at calibration
  float threshold_dn() const { return threshold_; }
  ContactState state() const { return state_; }

 private:
  void reduce(const image::ImageView& frame);  // frame -> blocks_
  float score() const;

  ContactGateOptions options_;
  int32_t width_ = 0, height_ = 0, channels_ = 0;
  std::vector<int32_t> block_of_column_, block_of_row_;
  std::vector<float> blocks_, sums_, counts_;
  std::vector<float> reference_, mean_, m2_;  // reference; calibration's running mean and M2
  int32_t calibrated_frames_ = 0;
  float noise_sigma_ = 0, threshold_ = 0;
  int32_t below_ = 0;
  ContactState state_ = ContactState::kCalibrating;
};

}  // namespace tlvlink::pipeline
