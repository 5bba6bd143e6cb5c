#pragma once
// What is pressed into the gel, how hard, and with what shear: the input of one rendered frame.
// All lengths in mm unless the name says otherwise; forces in N; moduli in Pa.

#include <cstdint>
#include <vector>

namespace tlvlink::sim {

enum class Shape : uint8_t {
  kNone,       // no object: the frame is background (+ markers, noise)
  kSphere,     // radius_mm (radii under 0.75 px are drawn as 0.75 px)
  kCylinder,   // radius_mm, length_mm, axis at angle_deg in the gel plane (a capsule)
  kFlatPlate,  // covers the whole gel: full-frame contact
  kBoxEdge,    // a flat face with a sharp straight edge along angle_deg through the centre
  kPoint,      // a 30 deg half-angle cone whose tip has radius radius_mm (may be 0)
  kHeightMap,  // height_map_mm (height x width of the processed frame, row-major), higher =
               // closer to gel; moved by whole pixels by the centre offset and gross slip
};

struct ObjectGeometry {
  Shape shape = Shape::kSphere;
  double radius_mm = 5.0;                       // sphere/cylinder/point tip [0, 1e6]
  double length_mm = 20.0;                      // cylinder [0, 1e6]
  double angle_deg = 0.0;                       // cylinder axis / edge direction [-360, 360]
  double center_x_mm = 0.0, center_y_mm = 0.0;  // offset from the gel centre [-1000, 1000]
  std::vector<float> height_map_mm;             // kHeightMap only
};

// Fractal surface texture added to the geometry (rough surfaces show high-frequency content).
// It is fixed to the object (moves with its centre and with gross slip) and has RMS sq_um over
// the part of the object in view.
struct SurfaceTexture {
  double sq_um = 0.5;                  // RMS roughness [0, 500]
  double correlation_length_mm = 0.3;  // [0.01, 20]
  double hurst = 0.8;                  // [0, 1]
  uint64_t seed = 0;
};

struct ObjectMechanics {
  double modulus_pa = 70e9;      // E_o [1e2, 1e13]
  double poisson = 0.33;         // nu_o [0, 0.5]
  double local_radius_mm = 5.0;  // L_o in the compliance split [0.01, 1e6]
  // Thickness of a compliant layer over a rigid backing (fabric on a table, a leather cover, a
  // stack of paper, turf) [0, 1e6]; 0 = bulk material. A layer cannot be compressed by more
  // than kMaxLayerStrain of its thickness: beyond that the rest of the approach goes into the
  // gel (tools/sim/REFERENCE.md "Soft layers bottom out").
  double layer_mm = 0.0;
};

struct Loading {
  // Exactly one of these drives the normal direction: force_n >= 0 (bisection on the press
  // depth), or press_mm >= 0 with force_n < 0.
  double force_n = 5.0;                     // [0, 1000]; < 0: use press_mm
  double press_mm = -1.0;                   // [0, 20]
  double shear_x_n = 0.0, shear_y_n = 0.0;  // tangential load Q in the gel plane [-1000, 1000]
  double torque_nmm = 0.0;                  // M_z [-1e5, 1e5], positive turns +x toward +y
  double friction = 0.6;                    // mu [0, 5]
  // Gross-slip travel of the imprint relative to the markers [0, 50], along Q (or +y, gravity,
  // without Q); only applied when the load exceeds the friction limit (rho >= 1).
  double slip_mm = 0.0;
};

struct ContactScene {
  ObjectGeometry geometry;
  SurfaceTexture texture;
  ObjectMechanics mechanics;
  Loading loading;
};

// Per-render camera settings (the sensor profile holds the fixed ones).
struct RenderOptions {
  bool markers = false;          // draw the marker grid (profile's marker layout)
  double led_gain = 1.0;         // [0, 100]; > 1 saturates, 0 = LEDs off (black frame)
  double noise_sigma_dn = -1.0;  // < 0: profile's value; else [0, 50]
  int32_t jpeg_quality = 0;      // 0: no JPEG round trip; else [1, 100]
  int32_t jpeg_passes = 1;       // [1, 4] (Feel frames were compressed twice)
};

}  // namespace tlvlink::sim
