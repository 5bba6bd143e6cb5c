#include "tlvlink/pipeline/contact_gate.h"

#include <algorithm>
#include <cmath>

namespace tlvlink::pipeline {

Status validate(const ContactGateOptions& o) {
  TLV_ENSURE(o.reference_frames >= 1 && o.reference_frames <= 1000, ErrorCode::kInvalidArgument,
             "contact.reference_frames %d outside [1, 1000]", o.reference_frames);
  TLV_ENSURE(o.grid_width >= 1 && o.grid_width <= 256 && o.grid_height >= 1 && o.grid_height <= 256,
             ErrorCode::kInvalidArgument, "contact grid %dx%d outside [1, 256]", o.grid_width,
             o.grid_height);
  TLV_ENSURE(o.noise_multiple > 0 && o.noise_multiple <= 1000, ErrorCode::kInvalidArgument,
             "contact.noise_multiple %g outside (0, 1000]", static_cast<double>(o.noise_multiple));
  TLV_ENSURE(o.min_threshold_dn >= 0 && o.min_threshold_dn <= 255, ErrorCode::kInvalidArgument,
             "contact.min_threshold_dn %g outside [0, 255]",
             static_cast<double>(o.min_threshold_dn));
  TLV_ENSURE(o.release_fraction > 0 && o.release_fraction <= 1, ErrorCode::kInvalidArgument,
             "contact.release_fraction %g outside (0, 1]", static_cast<double>(o.release_fraction));
  TLV_ENSURE(o.release_frames >= 1 && o.release_frames <= 1000, ErrorCode::kInvalidArgument,
             "contact.release_frames %d outside [1, 1000]", o.release_frames);
  TLV_ENSURE(o.drift_rate >= 0 && o.drift_rate < 1, ErrorCode::kInvalidArgument,
             "contact.drift_rate %g outside [0, 1)", static_cast<double>(o.drift_rate));
  return {};
}

const char* contact_state_name(ContactState s) {
  switch (s) {
    case ContactState::kCalibrating: return "calibrating";
    case ContactState::kNoContact: return "none";
    case ContactState::kContact: return "contact";
  }
  return "?";
}

Result<ContactGate> ContactGate::create(int32_t width, int32_t height, int32_t channels,
                                        const ContactGateOptions& options) {
  TLV_TRY(validate(options));
  TLV_ENSURE(width >= 1 && height >= 1 && (channels == 1 || channels == 3),
             ErrorCode::kInvalidArgument, "contact gate for %dx%dx%d frames", width, height,
             channels);
  ContactGate g;
  g.options_ = options;
  g.options_.grid_width = std::min(options.grid_width, width);
  g.options_.grid_height = std::min(options.grid_height, height);
  g.width_ = width;
  g.height_ = height;
  g.channels_ = channels;
  for (int32_t x = 0; x < width; ++x)
    g.block_of_column_.push_back(x * g.options_.grid_width / width);
  for (int32_t y = 0; y < height; ++y)
    g.block_of_row_.push_back(y * g.options_.grid_height / height);
  const size_t n = static_cast<size_t>(g.options_.grid_width) *
                   static_cast<size_t>(g.options_.grid_height) * static_cast<size_t>(channels);
  g.blocks_.assign(n, 0);
  g.sums_.assign(n, 0);
  g.counts_.assign(n, 0);
  for (int32_t y = 0; y < height; ++y)
    for (int32_t x = 0; x < width; ++x)
      for (int32_t c = 0; c < channels; ++c)
        g.counts_[(static_cast<size_t>(g.block_of_row_[static_cast<size_t>(y)]) *
                       static_cast<size_t>(g.options_.grid_width) +
                   static_cast<size_t>(g.block_of_column_[static_cast<size_t>(x)])) *
                      static_cast<size_t>(channels) +
                  static_cast<size_t>(c)] += 1;
  g.reference_.assign(n, 0);
  g.mean_.assign(n, 0);
  g.m2_.assign(n, 0);
  return g;
}

void ContactGate::reduce(const image::ImageView& f) {
  std::fill(sums_.begin(), sums_.end(), 0.0f);
  const auto gw = static_cast<size_t>(options_.grid_width);
  const auto ch = static_cast<size_t>(channels_);
  for (int32_t y = 0; y < height_; ++y) {
    const uint8_t* row = f.row(y);
    float* sums =
        sums_.data() + static_cast<size_t>(block_of_row_[static_cast<size_t>(y)]) * gw * ch;
    for (int32_t x = 0; x < width_; ++x) {
      float* s = sums + static_cast<size_t>(block_of_column_[static_cast<size_t>(x)]) * ch;
      for (size_t c = 0; c < ch; ++c) s[c] += row[static_cast<size_t>(x) * ch + c];
    }
  }
  for (size_t i = 0; i < blocks_.size(); ++i) blocks_[i] = sums_[i] / counts_[i];
}

float ContactGate::score() const {
  float worst = 0;
  for (size_t i = 0; i < blocks_.size(); ++i)
    worst = std::max(worst, std::fabs(blocks_[i] - reference_[i]));
  return worst;
}

Status ContactGate::contact_mask(std::span<uint8_t> bits) const {
  const auto cells =
      static_cast<size_t>(options_.grid_width) * static_cast<size_t>(options_.grid_height);
  TLV_ENSURE(bits.size() == (cells + 7) / 8, ErrorCode::kInvalidArgument,
             "contact mask: %zu bytes for %zu cells", bits.size(), cells);
  std::fill(bits.begin(), bits.end(), uint8_t{0});
  if (state_ == ContactState::kCalibrating) return {};
  const auto ch = static_cast<size_t>(channels_);
  for (size_t cell = 0; cell < cells; ++cell) {
    bool hit = false;
    for (size_t c = 0; c < ch; ++c)
      hit |= std::fabs(blocks_[cell * ch + c] - reference_[cell * ch + c]) > threshold_;
    if (hit) bits[cell / 8] = static_cast<uint8_t>(bits[cell / 8] | (1u << (cell % 8)));
  }
  return {};
}

void ContactGate::rezero() {
  calibrated_frames_ = 0;
  state_ = ContactState::kCalibrating;
  below_ = 0;
  threshold_ = 0;
}

Result<ContactDecision> ContactGate::update(const image::ImageView& f) {
  TLV_ENSURE(
      f.pixels != nullptr && f.width == width_ && f.height == height_ && f.channels == channels_,
      ErrorCode::kShapeMismatch, "contact gate: frame %dx%dx%d, expected %dx%dx%d", f.width,
      f.height, f.channels, width_, height_, channels_);
  reduce(f);
  ContactDecision d;
  if (state_ == ContactState::kCalibrating) {
    // Welford's running mean and variance per block: the reference and its noise.
    const float k = static_cast<float>(++calibrated_frames_);
    for (size_t i = 0; i < blocks_.size(); ++i) {
      const float delta = blocks_[i] - mean_[i];
      mean_[i] += delta / k;
      m2_[i] += delta * (blocks_[i] - mean_[i]);
    }
    if (calibrated_frames_ < options_.reference_frames) return d;
    double variance = 0;
    for (float m2 : m2_) variance += static_cast<double>(m2);
    variance /= static_cast<double>(m2_.size()) * std::max(1.0, static_cast<double>(k) - 1);
    noise_sigma_ = static_cast<float>(std::sqrt(variance));
    threshold_ = std::max(options_.min_threshold_dn, options_.noise_multiple * noise_sigma_);
    reference_ = mean_;  // same size: copies into the existing buffer
    std::fill(mean_.begin(), mean_.end(), 0.0f);
    std::fill(m2_.begin(), m2_.end(), 0.0f);
    state_ = ContactState::kNoContact;
    // The frame that completes the reference is judged against it like any later one: a touch
    // that began during calibration is contact now, as its mask already shows.
  }
  d.score_dn = score();
  d.threshold_dn = threshold_;
  if (state_ == ContactState::kNoContact) {
    if (d.score_dn > threshold_) {
      state_ = ContactState::kContact;
      below_ = 0;
      d.onset = true;
    } else if (options_.drift_rate > 0) {
      for (size_t i = 0; i < reference_.size(); ++i)
        reference_[i] += options_.drift_rate * (blocks_[i] - reference_[i]);
    }
  } else if (d.score_dn < options_.release_fraction * threshold_) {
    if (++below_ >= options_.release_frames) {
      state_ = ContactState::kNoContact;
      d.release = true;
    }
  } else {
    below_ = 0;
  }
  d.state = state_;
  return d;
}

}  // namespace tlvlink::pipeline
