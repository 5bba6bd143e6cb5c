#pragma once
// The GelSight frame renderer: contact mechanics (compliance split, force bisection, membrane
// spreading), photometric shading over a non-uniform background, markers with normal dilation
// and shear/slip fields, blur, noise, vignetting, optional JPEG. See tools/sim/REFERENCE.md for the
// model.
//
// A Renderer owns its scratch buffers: after the first frame of a given size, render() does
// not allocate (it will later serve as the live simulated sensor in the streaming pipeline).
// One Renderer per thread; the background of a sensor instance is fixed by `sensor_seed`.

#include <cstdint>
#include <memory>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/sim/scene.h"
#include "tlvlink/sim/sensor.h"
#include "tlvlink/touch/contact_state.h"

namespace tlvlink::sim {

// The contact's physical state is tools/touch's (the datasets record it with every frame).
using touch::ContactState;

// Pixel coordinates with pixel (i, j)'s centre at x = i, y = j.
struct Marker {
  float x0, y0;  // rest position (px)
  float x, y;    // displaced position (px): shear field + normal dilation
};

struct Frame {
  int32_t height = 0, width = 0;  // the profile's processed size
  std::vector<uint8_t> rgb;       // height * width * 3, row-major, interleaved RGB
  ContactState state;
  std::vector<Marker> markers;  // empty unless RenderOptions::markers
};

class Renderer {
 public:
  // Validates the profile; builds the sensor's background (seeded by sensor_seed).
  static Result<std::unique_ptr<Renderer>> create(const SensorProfile& profile,
                                                  uint64_t sensor_seed);
  virtual ~Renderer() = default;

  // Renders one frame into `out` (reusing its buffers). `noise_seed` drives the camera noise
  // and any per-frame randomness, so (scene, options, noise_seed) -> identical bytes.
  // Non-finite or out-of-range scene/options values are an error naming the field. Markers are
  // drawn when both options.markers and profile().markers are set. No allocation after the
  // first call with a given `out`, except for the JPEG round trip (jpeg_quality > 0).
  virtual Status render(const ContactScene& scene, const RenderOptions& options,
                        uint64_t noise_seed, Frame& out) = 0;

  // The no-contact background (before noise) of this sensor instance, height*width*3.
  virtual const std::vector<uint8_t>& background() const = 0;
  virtual const SensorProfile& profile() const = 0;
};

// Parameter checks shared by render() and the dataset generators.
Status validate(const ContactScene& scene);
Status validate(const RenderOptions& options);

}  // namespace tlvlink::sim
