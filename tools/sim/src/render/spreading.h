#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "spreading.h is internal to tools/sim: include its public headers instead"
#endif
// Membrane spreading (gelsight-sim.md step 4, Taxim-style): the gel surface around a contact is
// pulled down with it. z = -u_g is blurred at six shrinking scales (0.90 ... 0.03 mm, scaled by
// t_g / 4 mm); after each blur the core of the contact (u > 0.4 max u) gets its indentation back;
// a final 5x5 blur softens the core edge. Work is limited to a region of interest: the contact's
// bounding box grown by 3.5 sigma of the combined blur (beyond it z < 0.3 % of the depth).

#include <cstdint>
#include <vector>

#include "render/blur.h"
#include "render/contact.h"
#include "render/sensor_tables.h"

namespace tlvlink::sim::internal {

// The six blur scales in pixels for this gel and grid.
std::vector<double> spreading_sigmas_px(double gel_thickness_mm, double mm_per_px);

class MembraneSpreading {
 public:
  MembraneSpreading(const FrameGrid& grid, double gel_thickness_mm);  // the only allocation

  // Region that the spread of this contact can reach.
  Roi roi(const ContactSolution& contact) const;

  // Returns z (mm, toward the object > 0, i.e. <= 0 in a press) over `roi`, row stride
  // roi.width(). `u_gel` is frame-sized; max_gel is its maximum.
  PlaneView spread(const float* u_gel, double max_gel, Roi roi, GaussianBlur& blur);

 private:
  FrameGrid grid_;
  double sigmas_px_[6] = {};
  int32_t margin_px_ = 0;
  std::vector<float> z_, u_;
};

}  // namespace tlvlink::sim::internal
