#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "contact.h is internal to tools/sim: include its public headers instead"
#endif
// Normal contact (gelsight-sim.md steps 1-3): gap, compliance split kappa, the force model
// (Winkler layer + membrane tension, model_constants.h) and the force -> press-depth solve.
//
// F(delta) = kappa * (k_w s^2 sum_{g < delta} (delta - g) + T sum_{g < delta} L)
// with g = max h - h the gap, L the tension curvature term (geometry.h), k_w = chi E*_g / t_g,
// T = psi E_g t_g / (6 (1 + nu_g)). F is non-decreasing in delta, so the solve is a bisection;
// a histogram of the gap gives F at 1024 bin edges in one pass and the bisection then only
// touches the pixels of one bin. A capped layer (Compliance::capped) gives each pixel the gel
// share u_g = max(kappa a, a - cap) of its approach a = delta - g, F = k_w s^2 sum u_g +
// T sum L u_g / a (still non-decreasing); that case is solved by plain bisection.

#include <cstdint>
#include <vector>

#include "render/sensor_tables.h"
#include "tlvlink/sim/scene.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim::internal {

struct Compliance {
  double kappa = 1;         // fraction of the approach taken by the gel, (0, 1]
  double winkler = 0;       // k_w, N/mm^3
  double tension = 0;       // T, N/mm
  double max_gel_mm = 0;    // u_g cap, kMaxGelStrain * t_g
  double max_press_mm = 0;  // max_gel_mm / kappa
  // A compliant layer (ObjectMechanics::layer_mm) takes at most layer_cap_mm = kMaxLayerStrain
  // * layer of the approach; where (1 - kappa) a would exceed it the gel takes the rest:
  // u_g = max(kappa a, a - layer_cap_mm). `capped` when a press within max_press_mm can reach
  // the cap (never for stiff objects, whose share 1 - kappa is tiny); the gel then reaches
  // max_gel_mm already at capped_max_press_mm.
  bool capped = false;
  double layer_cap_mm = 0;
  double capped_max_press_mm = 0;
};

// The compliance split of the bulk (object shape): kappa = C_g t_g / (C_g t_g + C_o L_o).
Compliance compliance(const SensorProfile& sensor, const ObjectMechanics& object);

// The share of the object's texture the gel takes: the same split, but at the texture's own
// length scale l = correlation length, where each body responds to a corrugation of wavelength l
// over a depth ~l (a half-space; Johnson, Contact Mechanics, ch. 13), or over its thickness when
// it is thinner: C_g min(l, t_g) / (C_g min(l, t_g) + C_o min(l, layer)). A soft object's texture
// therefore flattens more than its bulk imprint: the texture's asperities give way instead of
// the gel (gelsight-sim.md, "soft materials conform"). About 1 for stiff objects.
double texture_split(const SensorProfile& sensor, const ObjectMechanics& object,
                     const SurfaceTexture& texture);

struct ContactSolution {
  bool in_contact = false;
  double press_mm = 0, force_n = 0, max_gel_mm = 0;
  int64_t pixels = 0;
  double area_mm2 = 0;
  double centroid_x_mm = 0, centroid_y_mm = 0;  // of the contact area, from the gel centre
  int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;       // bounding box [x0, x1) x [y0, y1), empty if none
};

class ContactSolver {
 public:
  explicit ContactSolver(const FrameGrid& grid);  // the only allocation

  // Stores the gap of surface h (mm) and the tension term for the solves below. `surface` bounds
  // the pixels where the object has a surface (geometry.h surface_bounds); nothing outside it
  // is read. An empty `surface` means nothing can touch.
  void prepare(const float* h, const float* curvature, const Compliance& c, Roi surface);
  // Press depth that produces `force_n` (clamped to [0, max_press_mm]).
  double press_for_force(double force_n);
  double force_at(double press_mm) const;
  // Gel indentation u_g (grid.pixels() floats, 0 outside the contact) and its summary.
  ContactSolution indent(double press_mm, float* u_gel) const;

 private:
  FrameGrid grid_;
  Compliance c_;
  double area_px_ = 0;  // s^2
  std::vector<float> gap_;
  const float* curvature_ = nullptr;
  Roi surface_;
  double gap_max_ = 0;  // over pixels with object surface
  std::vector<double> bin_count_, bin_gap_, bin_curv_;
  std::vector<float> in_bin_gap_, in_bin_curv_;

  // Whether a press this deep compresses the layer to its cap somewhere (Compliance::capped).
  // Below it every formula and every byte is the uncapped one.
  bool cap_reached(double press_mm) const {
    return c_.capped && (1 - c_.kappa) * press_mm > c_.layer_cap_mm;
  }
  double capped_force_at(double press_mm) const;
  double uncapped_press_for_force(double force_n);  // the histogram solve
};

}  // namespace tlvlink::sim::internal
