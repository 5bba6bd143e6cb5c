#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "markers.h is internal to tools/sim: include its public headers instead"
#endif
// Marker dots: the normal-dilation field of a press (FOTS: markers are pushed outward around an
// indentation) and drawing dark Gaussian dots into the colour-change planes.
//
// Dilation(x) = c_d * integral u_g(x') (x - x') exp(-lambda_d |x - x'|^2) dA', evaluated from
// 4x4-pixel block sums of u_g with separable exponentials (a few thousand exp per frame).

#include <array>
#include <cstdint>
#include <vector>

#include "render/contact.h"
#include "render/sensor_tables.h"
#include "render/spreading.h"

namespace tlvlink::sim::internal {

class MarkerPainter {
 public:
  MarkerPainter(const FrameGrid& grid, const SensorProfile& profile);  // the only allocation

  // Block sums of the gel indentation for dilation(); call once per frame with a contact.
  void prepare_dilation(const float* u_gel, const ContactSolution& contact);
  // Outward displacement (mm) of the gel point at (x, y) mm; 0 without a prepared contact.
  std::array<double, 2> dilation(double x_mm, double y_mm);

  // Darkens the pre-blur colour planes with a dot centred at (x_px, y_px): the light through the
  // dot falls to 15 % at its centre, I -> I (1 - m), i.e. delta -= (background + delta) m.
  // Grows `dirty` by the touched pixels.
  void draw(double x_px, double y_px, const std::array<const float*, 3>& background,
            const std::array<float*, 3>& delta, Roi& dirty);

 private:
  FrameGrid grid_;
  static constexpr int32_t kBlock = 4;
  int32_t blocks_x_ = 0, blocks_y_ = 0;
  std::vector<float> block_u_;                     // mm^3 per block
  int32_t bx0_ = 0, by0_ = 0, bx1_ = 0, by1_ = 0;  // blocks holding contact, [bx0, bx1)
  std::vector<double> ex_, ey_;
  double sigma_px_ = 1;
  int32_t radius_px_ = 1;
  std::vector<float> dot_x_, dot_y_;
};

}  // namespace tlvlink::sim::internal
