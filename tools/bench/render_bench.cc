// Rendering speed of the GelSight simulator on a realistic mix of scenes, one Renderer per
// thread. Prints the median (and min/max) total frames/s over several repeats for each thread
// count, wall ms per frame per thread, and process CPU ms per frame (which a shared, busy
// machine inflates less than wall time).
//
//   tlvlink_render_bench [--frames N] [--threads-list 1,2] [--repeats R] [--sensor NAME]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tlvlink/sim/renderer.h"

namespace {

using tlvlink::sim::ContactScene;
using tlvlink::sim::RenderOptions;
using tlvlink::sim::Shape;

struct Job {
  ContactScene scene;
  RenderOptions options;
};

double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
}

// The mix a dataset run renders: mostly spheres and cylinders of varied size, force, texture
// and stiffness; some plates, edges, points and empty frames; a third with markers and shear.
std::vector<Job> scene_mix(int count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Job> jobs;
  for (int i = 0; i < count; ++i) {
    Job j;
    ContactScene& s = j.scene;
    const double pick = u(rng);
    s.geometry.shape = pick < 0.10   ? Shape::kNone
                       : pick < 0.50 ? Shape::kSphere
                       : pick < 0.65 ? Shape::kCylinder
                       : pick < 0.80 ? Shape::kFlatPlate
                       : pick < 0.92 ? Shape::kBoxEdge
                                     : Shape::kPoint;
    s.geometry.radius_mm = s.geometry.shape == Shape::kPoint ? u(rng) * 0.5 : 2 + 13 * u(rng);
    s.geometry.length_mm = 5 + 20 * u(rng);
    s.geometry.angle_deg = 360 * u(rng) - 180;
    s.geometry.center_x_mm = 8 * u(rng) - 4;
    s.geometry.center_y_mm = 6 * u(rng) - 3;
    s.texture.sq_um = log_uniform(rng, 0.2, 80);
    s.texture.correlation_length_mm = log_uniform(rng, 0.05, 3);
    s.texture.hurst = 0.3 + 0.6 * u(rng);
    s.texture.seed = rng();
    s.mechanics.modulus_pa = log_uniform(rng, 1e4, 1e11);
    s.mechanics.poisson = 0.3 + 0.2 * u(rng);
    s.loading.force_n = 0.5 + 19.5 * u(rng);
    s.loading.friction = 0.2 + u(rng);
    if (u(rng) < 0.33) {
      j.options.markers = true;
      const double q = 1.2 * u(rng) * s.loading.friction * s.loading.force_n;
      s.loading.shear_x_n = q * (u(rng) - 0.5);
      s.loading.shear_y_n = q * (u(rng) - 0.5);
      s.loading.torque_nmm = 20 * (u(rng) - 0.5);
      s.loading.slip_mm = u(rng) < 0.5 ? 2 * u(rng) : 0;
    }
    jobs.push_back(std::move(j));
  }
  return jobs;
}

std::vector<int> parse_list(const char* text) {
  std::vector<int> v;
  for (const char* p = text; *p != '\0';) {
    char* end = nullptr;
    const long x = std::strtol(p, &end, 10);
    if (end == p || x < 1 || x > 256) return {};
    v.push_back(static_cast<int>(x));
    p = *end == ',' ? end + 1 : end;
    if (*end != ',' && *end != '\0') return {};
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 400, repeats = 5;
  std::vector<int> threads_list = {1, 2};
  std::string sensor = "gelsight-mini";
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (std::strcmp(argv[i], "--frames") == 0 && has_value) {
      frames = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--repeats") == 0 && has_value) {
      repeats = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--threads-list") == 0 && has_value) {
      threads_list = parse_list(argv[++i]);
    } else if (std::strcmp(argv[i], "--sensor") == 0 && has_value) {
      sensor = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: %s [--frames N] [--threads-list 1,2] [--repeats R] [--sensor NAME]\n",
                   argv[0]);
      return 2;
    }
  }
  if (frames < 1 || repeats < 1 || threads_list.empty()) {
    std::fprintf(stderr, "error: --frames and --repeats must be >= 1, --threads-list like 1,2\n");
    return 2;
  }
  auto profile = tlvlink::sim::sensor_profile(sensor);
  if (!profile.ok()) {
    std::fprintf(stderr, "error: %s\n", profile.error().message());
    return 2;
  }
  const std::vector<Job> jobs = scene_mix(256, 20240601);
  std::printf(
      "tlvlink_render_bench: %s %dx%d, %zu-scene mix (10%% empty, 40%% sphere, 15%% cylinder, "
      "15%% plate, 12%% edge, 8%% point; 1/3 with markers + shear), %d frames/thread, "
      "%d repeats\n",
      sensor.c_str(), profile->height, profile->width, jobs.size(), frames, repeats);
  std::printf("%-8s %12s %10s %10s %16s %14s\n", "threads", "fps(median)", "fps(min)", "fps(max)",
              "ms/frame/thread", "cpu ms/frame");
  for (int threads : threads_list) {
    std::vector<std::unique_ptr<tlvlink::sim::Renderer>> renderers;
    std::vector<tlvlink::sim::Frame> out(static_cast<size_t>(threads));
    for (int t = 0; t < threads; ++t) {
      auto r = tlvlink::sim::Renderer::create(profile.value(), 7);
      if (!r.ok()) {
        std::fprintf(stderr, "error: %s\n", r.error().message());
        return 1;
      }
      renderers.push_back(std::move(r.value()));
    }
    std::atomic<int> failures{0};
    auto work = [&](int t, int count, int offset) {
      for (int k = 0; k < count; ++k) {
        const Job& j = jobs[static_cast<size_t>(offset + k) % jobs.size()];
        if (!renderers[static_cast<size_t>(t)]
                 ->render(j.scene, j.options, static_cast<uint64_t>(k), out[static_cast<size_t>(t)])
                 .ok()) {
          failures.fetch_add(1);
        }
      }
    };
    for (int t = 0; t < threads; ++t) work(t, 32, t * 97);  // warm-up: first-frame setup
    std::vector<double> fps, cpu_ms;
    for (int rep = 0; rep < repeats; ++rep) {
      const std::clock_t cpu_start = std::clock();
      const auto start = std::chrono::steady_clock::now();
      std::vector<std::thread> pool;
      for (int t = 0; t < threads; ++t) pool.emplace_back(work, t, frames, t * 97 + rep * 13);
      for (auto& th : pool) th.join();
      const double s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      fps.push_back(static_cast<double>(frames) * threads / s);
      cpu_ms.push_back(1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC /
                       (static_cast<double>(frames) * threads));
    }
    if (failures.load() != 0) {
      std::fprintf(stderr, "error: %d renders failed\n", failures.load());
      return 1;
    }
    std::sort(fps.begin(), fps.end());
    std::sort(cpu_ms.begin(), cpu_ms.end());
    const double median = fps[fps.size() / 2];
    std::printf("%-8d %12.1f %10.1f %10.1f %16.3f %14.3f\n", threads, median, fps.front(),
                fps.back(), 1000.0 * threads / median, cpu_ms[cpu_ms.size() / 2]);
  }
  return 0;
}
