// live_path_frames: render the same scenes three ways and write them
// (tools/eval/live_path/README.md):
//   NNNN_p.ppm  the processed render (RawFrame::processed)
//   NNNN_j.jpg  the processed render as a dataset writer stores it (encode_jpeg q90, 4:2:0)
//   NNNN_r.ppm  the raw MJPEG 3280x2464 (q90, 4:2:2) recovered by RawDecoder (= the daemon's
//               FrameDecoder with the gelsight-mini SensorView)
// Scene sets: "touch" (touch-session presses, copied from touch_generator.cc make_press),
// "grasp" (GraspEpisodeGenerator "during" scenes, finger A, as `tlvlink sim scenario` animates
// them). Usage: live_path_frames SET N SEED MARKERS OUTDIR   (MARKERS 0, 1, or -1 = half of the
// scenes) Writes OUTDIR/labels.jsonl (one line per scene) and, for scenes 0-2, NNNN_raw.jpg (the
// MJPEG).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <span>
#include <string>

#include "tlvlink/image/jpeg.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/materials.h"
#include "tlvlink/sim/raw_camera.h"
#include "tlvlink/sim/sensor.h"

using namespace tlvlink;
using namespace tlvlink::sim;

// SplitMix64: this tool's own draws (the scenes follow the touch generator's distributions, not
// its exact streams).
class Rng {
 public:
  explicit Rng(uint64_t seed) : s_(seed) {}
  uint64_t next() {
    uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  int32_t int_in(int32_t lo, int32_t hi) {
    return static_cast<int32_t>(lo +
                                static_cast<int64_t>(next() % static_cast<uint64_t>(hi - lo + 1)));
  }
  bool bernoulli(double p) { return uniform() < p; }
  size_t weighted(std::span<const double> w) {
    double total = 0;
    for (double x : w) total += x;
    double r = uniform() * total;
    for (size_t i = 0; i < w.size(); ++i) {
      if (r < w[i]) return i;
      r -= w[i];
    }
    return w.size() - 1;
  }

 private:
  uint64_t s_;
};

static void write_ppm(const std::string& path, const uint8_t* rgb, int w, int h) {
  FILE* f = std::fopen(path.c_str(), "wb");
  std::fprintf(f, "P6\n%d %d\n255\n", w, h);
  std::fwrite(rgb, 1, static_cast<size_t>(w) * h * 3, f);
  std::fclose(f);
}

// touch_generator.cc make_press, with this tool's Rng.
static ContactScene touch_scene(const MaterialSample& m, uint64_t texture_seed, Rng& rng,
                                double& force) {
  const MaterialClass& cls = *material_class(m.class_id).value();
  ContactScene s;
  const auto shape = static_cast<PressShape>(rng.weighted(cls.press_shapes));
  ObjectGeometry& g = s.geometry;
  g.center_x_mm = rng.uniform(-3, 3);
  g.center_y_mm = rng.uniform(-3, 3);
  g.angle_deg = rng.uniform(0, 180);
  double radius = 0;
  switch (shape) {
    case PressShape::kSphere:
      g.shape = Shape::kSphere;
      g.radius_mm = radius = rng.log_uniform(2, 25);
      break;
    case PressShape::kCylinder:
      g.shape = Shape::kCylinder;
      g.radius_mm = radius = rng.log_uniform(2, 20);
      g.length_mm = rng.uniform(20, 100);
      break;
    case PressShape::kFlat:
      if (m.rough == 1) {
        g.shape = Shape::kFlatPlate;
        radius = 20;
      } else {
        g.shape = Shape::kSphere;
        g.radius_mm = radius = rng.log_uniform(25, 80);
      }
      break;
    case PressShape::kEdge:
      g.shape = Shape::kBoxEdge;
      radius = 10;
      break;
  }
  s.mechanics.local_radius_mm = compliant_length_mm(m, radius);
  s.mechanics.layer_mm = m.layer_mm;
  force = rng.log_uniform(1, 15);
  s.texture.sq_um = m.sq_um;
  s.texture.correlation_length_mm = m.correlation_length_mm;
  s.texture.hurst = m.hurst;
  s.texture.seed = texture_seed;
  s.mechanics.modulus_pa = m.modulus_pa;
  s.mechanics.poisson = m.poisson;
  Loading& l = s.loading;
  l.force_n = force;
  l.friction = m.friction;
  const double q = rng.uniform(0, 0.3) * m.friction * force;
  const double dir = rng.uniform(0, 2 * std::numbers::pi);
  l.shear_x_n = q * std::cos(dir);
  l.shear_y_n = q * std::sin(dir);
  l.torque_nmm = rng.uniform(-0.1, 0.1) * m.friction * force;
  return s;
}

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: live_path_frames touch|grasp N SEED MARKERS(0|1|-1) OUTDIR\n");
    return 2;
  }
  const std::string set = argv[1];
  const int n = std::atoi(argv[2]);
  const uint64_t seed = std::strtoull(argv[3], nullptr, 10);
  const int markers_opt = std::atoi(argv[4]);
  const std::string out = argv[5];
  const SensorProfile profile = sensor_profile("gelsight-mini").value();
  auto decoder = RawDecoder::create(profile).value();
  std::unique_ptr<GraspEpisodeGenerator> grasp;
  if (set == "grasp") {
    GraspSetOptions go;
    go.objects = n;
    go.grasps_per_object = 1;
    go.vision_height = go.vision_width = 8;
    go.seed = seed;
    go.sensor_instances = 64;
    grasp = GraspEpisodeGenerator::create(go).value();
  }
  FILE* labels = std::fopen((out + "/labels.jsonl").c_str(), "w");
  RawFrame raw;
  std::vector<uint8_t> rec;
  Rng top(seed * 7919 + 17);
  for (int i = 0; i < n; ++i) {
    ContactScene scene;
    MaterialSample m;
    uint64_t sensor_seed = 0;
    double force = 0;
    if (grasp) {
      GraspEpisode ep;
      GraspScenes sc;
      if (!grasp->generate(i, ep, sc).ok()) return 1;
      scene = sc.during[0];
      if (scene.geometry.shape == Shape::kNone) scene = sc.during[1];
      m = ep.material;
      sensor_seed = sc.sensor_seed[0];
      force = scene.loading.force_n;
    } else {
      const int32_t cls = top.int_in(0, kMaterialClassCount - 1);
      m = sample_material(cls, top.next()).value();
      const uint64_t tex = top.next();
      scene = touch_scene(m, tex, top, force);
      sensor_seed = top.next();
    }
    RenderOptions ro;
    ro.markers = markers_opt < 0 ? top.bernoulli(0.5) : markers_opt != 0;
    auto cam = RawCamera::create(profile, sensor_seed).value();
    Status st = cam->render(scene, ro, seed * 1000003 + static_cast<uint64_t>(i), raw);
    if (!st.ok()) {
      std::fprintf(stderr, "render %d: %s\n", i, st.error().message());
      return 1;
    }
    char name[64];
    std::snprintf(name, sizeof name, "%s/%04d", out.c_str(), i);
    const Frame& p = raw.processed;
    write_ppm(std::string(name) + "_p.ppm", p.rgb.data(), p.width, p.height);
    image::Image im{p.width, p.height, 3, p.rgb};
    auto jpg = image::encode_jpeg(im, 90).value();
    FILE* f = std::fopen((std::string(name) + "_j.jpg").c_str(), "wb");
    std::fwrite(jpg.data(), 1, jpg.size(), f);
    std::fclose(f);
    if (!decoder->recover(raw.bytes, rec).ok()) return 1;
    write_ppm(std::string(name) + "_r.ppm", rec.data(), p.width, p.height);
    if (i < 3) {
      f = std::fopen((std::string(name) + "_raw.jpg").c_str(), "wb");
      std::fwrite(raw.bytes.data(), 1, raw.bytes.size(), f);
      std::fclose(f);
    }
    std::fprintf(labels,
                 "{\"i\":%d,\"material\":\"%s\",\"rough\":%d,\"force\":%.3f,\"shape\":%d,"
                 "\"radius\":%.2f,\"contact\":%d,\"area\":%.2f,\"markers\":%d}\n",
                 i, material_classes()[static_cast<size_t>(m.class_id)].name.data(), m.rough, force,
                 static_cast<int>(scene.geometry.shape), scene.geometry.radius_mm,
                 p.state.in_contact ? 1 : 0, p.state.contact_area_mm2, ro.markers ? 1 : 0);
  }
  std::fclose(labels);
  return 0;
}
