// The raw camera's frame loop does not allocate after the first frames (STYLE.md: setup
// allocates, the frame loop does not; it is the simulated sensor of the capture pipeline):
// RawCamera::render and RawDecoder::recover, counted through operator new by
// support/alloc_counter. libjpeg-turbo's own per-image work memory comes from malloc inside
// tjCompress2/tjDecompress2 and is not counted (the TurboJPEG API offers no way to keep it).
#include <vector>

#include <gtest/gtest.h>

#include "sim/render/render_test_util.h"
#include "support/alloc_counter.h"
#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim {
namespace {

size_t raw_allocations_in_steady_state(std::string_view name) {
  const SensorProfile p = sensor_profile(name).value();
  auto camera = RawCamera::create(p, 1);
  auto decoder = RawDecoder::create(p);
  EXPECT_TRUE(camera.ok() && decoder.ok());
  if (!camera.ok() || !decoder.ok()) return 1;
  std::vector<ContactScene> scenes;
  scenes.push_back(testing::sphere(4));
  ContactScene plate = testing::sphere(10);  // reaches into the periphery
  plate.geometry.shape = Shape::kFlatPlate;
  plate.texture.sq_um = 20;
  scenes.push_back(plate);
  ContactScene none;
  none.geometry.shape = Shape::kNone;
  scenes.push_back(none);
  ContactScene map;  // a processed-size map, padded for the periphery
  map.geometry.shape = Shape::kHeightMap;
  map.geometry.height_map_mm.assign(static_cast<size_t>(p.height) * static_cast<size_t>(p.width),
                                    0.0f);
  map.geometry.height_map_mm[static_cast<size_t>(p.height / 2 * p.width + p.width / 2)] = 0.3f;
  scenes.push_back(map);
  RenderOptions o;
  o.markers = true;
  RawFrame raw;
  std::vector<uint8_t> rgb;
  for (const ContactScene& s : scenes) {  // warm-up: first frames size every buffer
    EXPECT_TRUE((*camera)->render(s, o, 1, raw).ok());
    EXPECT_TRUE((*decoder)->recover(raw.bytes, rgb).ok());
  }
  ::tlvlink::testing::start_counting_allocations();
  bool ok = true;
  for (int pass = 0; pass < 2; ++pass) {
    for (const ContactScene& s : scenes) {
      ok = (*camera)->render(s, o, 7, raw).ok() && ok;
      ok = (*decoder)->recover(raw.bytes, rgb).ok() && ok;
    }
  }
  const size_t allocations = ::tlvlink::testing::stop_counting_allocations();
  EXPECT_TRUE(ok);
  return allocations;
}

TEST(SimRenderNoAlloc, SteadyStateRawCameraDoesNotAllocate) {
  EXPECT_EQ(raw_allocations_in_steady_state("gelsight-mini"), 0u);  // MJPEG, periphery, 1/8 decode
  EXPECT_EQ(raw_allocations_in_steady_state("digit"), 0u);          // YUYV, transposed
  EXPECT_EQ(raw_allocations_in_steady_state("gelsight-r1.5"), 0u);  // MJPEG at the processed size
}

}  // namespace
}  // namespace tlvlink::sim
