#include "make_frames.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "tlvlink/sim/raw_camera.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::bench {

Status make_frames(const std::string& sensor, const std::string& dir, int count) {
  TLV_ASSIGN_OR_RETURN(const sim::SensorProfile profile, sim::sensor_profile(sensor));
  TLV_ASSIGN_OR_RETURN(auto camera, sim::RawCamera::create(profile, 1));
  std::filesystem::create_directories(dir);
  const bool mjpeg = camera->layout().format == sim::RawFormat::kMjpeg;
  sim::RawFrame raw;
  for (int i = 0; i < count; ++i) {
    sim::ContactScene scene;
    scene.geometry.shape = i % 5 == 4 ? sim::Shape::kNone : sim::Shape::kSphere;
    scene.geometry.radius_mm = 2.0 + (i % 7);
    scene.geometry.center_x_mm = -4.0 + (i % 9);
    scene.geometry.center_y_mm = -3.0 + (i % 5) * 1.5;
    scene.texture.sq_um = (i % 3 == 0) ? 40.0 : 0.5;
    scene.texture.seed = static_cast<uint64_t>(i);
    scene.loading.force_n = 1.0 + (i % 6);
    sim::RenderOptions options;
    options.markers = true;
    TLV_TRY(camera->render(scene, options, static_cast<uint64_t>(i), raw));
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%04d.%s", i, mjpeg ? "jpg" : "yuyv");
    std::ofstream out(dir + name, std::ios::binary);
    out.write(reinterpret_cast<const char*>(raw.bytes.data()),
              static_cast<std::streamsize>(raw.bytes.size()));
    TLV_ENSURE(out.good(), ErrorCode::kIo, "%s%s: write failed", dir.c_str(), name);
  }
  return {};
}

}  // namespace tlvlink::bench
