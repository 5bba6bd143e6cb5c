// render() must not allocate after the first frame (STYLE.md: setup allocates, the frame loop
// does not; the renderer will serve as the live simulated sensor), counted by
// support/alloc_counter. JPEG round trips are excluded (libturbojpeg allocates its buffers).
#include <vector>

#include <gtest/gtest.h>

#include "sim/render/render_test_util.h"
#include "support/alloc_counter.h"

namespace tlvlink::sim {
namespace {

struct Job {
  ContactScene scene;
  RenderOptions options;
};

std::vector<Job> jobs(int32_t height, int32_t width) {
  std::vector<Job> v;
  RenderOptions markers;
  markers.markers = true;
  auto add = [&](ContactScene s, RenderOptions o = {}) { v.push_back({std::move(s), o}); };
  add(testing::sphere(5));
  ContactScene none;
  none.geometry.shape = Shape::kNone;
  add(none, markers);
  ContactScene rough = testing::sphere(8, 10);
  rough.texture = {40, 0.2, 0.5, 3};
  add(rough);
  ContactScene plate = testing::sphere(20);
  plate.geometry.shape = Shape::kFlatPlate;
  add(plate, markers);
  ContactScene slip = testing::sphere(5);
  slip.loading.shear_x_n = 10;
  slip.loading.torque_nmm = 30;
  slip.loading.slip_mm = 3;
  add(slip, markers);
  ContactScene shear = testing::sphere(5);
  shear.loading.shear_y_n = 2;
  add(shear, markers);
  ContactScene edge = testing::sphere(5);
  edge.geometry.shape = Shape::kBoxEdge;
  add(edge);
  ContactScene point = testing::sphere(2, 0);
  point.geometry.shape = Shape::kPoint;
  add(point, markers);
  ContactScene soft = testing::sphere(5);
  soft.mechanics.modulus_pa = 1e3;
  add(soft);
  ContactScene map;
  map.geometry.shape = Shape::kHeightMap;
  map.geometry.height_map_mm.assign(static_cast<size_t>(height) * static_cast<size_t>(width), 0.0f);
  map.geometry.height_map_mm[static_cast<size_t>(height / 2 * width + width / 2)] = 0.3f;
  add(map);
  RenderOptions led;
  led.led_gain = 10;
  led.noise_sigma_dn = 0;
  add(testing::sphere(5), led);
  return v;
}

size_t allocations_in_steady_state(std::string_view profile) {
  auto r = testing::make_renderer(profile);
  EXPECT_NE(r, nullptr);
  if (r == nullptr) return 1;
  const auto work = jobs(r->profile().height, r->profile().width);
  Frame f;
  for (const Job& j : work) EXPECT_TRUE(r->render(j.scene, j.options, 1, f).ok());  // warm-up
  ::tlvlink::testing::start_counting_allocations();
  bool ok = true;
  for (int pass = 0; pass < 2; ++pass) {
    for (const Job& j : work) ok = r->render(j.scene, j.options, 7, f).ok() && ok;
  }
  const size_t allocations = ::tlvlink::testing::stop_counting_allocations();
  EXPECT_TRUE(ok);
  return allocations;
}

TEST(SimRenderNoAlloc, SteadyStateRenderDoesNotAllocate) {
  EXPECT_EQ(allocations_in_steady_state("gelsight-mini"), 0u);
  EXPECT_EQ(allocations_in_steady_state("digit"), 0u);  // domed gel, portrait frame
  EXPECT_EQ(allocations_in_steady_state("gelsight-r1.5"), 0u);
}

TEST(SimRenderNoAlloc, TheCounterWorks) {
  ::tlvlink::testing::start_counting_allocations();
  auto* p = new std::vector<int>(10);
  const size_t allocations = ::tlvlink::testing::stop_counting_allocations();
  delete p;
  EXPECT_GE(allocations, 1u);
}

}  // namespace
}  // namespace tlvlink::sim
