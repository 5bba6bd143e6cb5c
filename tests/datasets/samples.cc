#include "datasets/samples.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace tlvlink::testing {

datasets::RgbImage smooth_image(int32_t height, int32_t width, uint64_t seed) {
  datasets::RgbImage img;
  img.height = height;
  img.width = width;
  img.rgb.resize(static_cast<size_t>(height) * static_cast<size_t>(width) * 3);
  const double phase = static_cast<double>(seed % 97) * 0.37;
  for (int32_t y = 0; y < height; ++y) {
    for (int32_t x = 0; x < width; ++x) {
      for (int32_t c = 0; c < 3; ++c) {
        const double v = 128 + 60 * std::sin(0.11 * x + 0.07 * y + phase + c) +
                         30 * std::cos(0.05 * y - 0.03 * x + 2 * phase);
        img.rgb[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3 +
                static_cast<size_t>(c)] = static_cast<uint8_t>(std::lround(v));
      }
    }
  }
  return img;
}

datasets::TouchSample touch_sample(int32_t session, int32_t frame) {
  datasets::TouchSample s;
  char name[32];
  std::snprintf(name, sizeof name, "20220101_0000%02d", session);
  s.session = name;
  s.frame_index = frame * 7 + 3;
  s.object_id = 100 + session;
  s.material.class_id = session % 20;
  s.material.modulus_pa = 1e6 * (session + 1);
  s.material.poisson = 0.3;
  s.material.friction = 0.5 + 0.01 * frame;
  s.material.sq_um = 0.5 * (frame + 1);
  s.material.correlation_length_mm = 0.3;
  s.material.hurst = 0.8;
  s.material.hard = session % 2 == 0;
  s.material.rough = frame % 3 - 1;
  s.contact.in_contact = true;
  s.contact.force_n = 1.5 + frame;
  s.contact.contact_area_mm2 = 12.25;
  s.contact.markers_deviating = frame;
  const uint64_t seed = static_cast<uint64_t>(session * 100 + frame);
  s.touch = smooth_image(24, 32, seed);
  s.vision = smooth_image(16, 20, seed + 5000);
  s.sentence_desc = "The surface of session " + std::to_string(session) +
                    " feels cool, \"quoted\" and smooth at frame " + std::to_string(frame) + ".";
  s.phrases = {"cool", "smooth", "frame " + std::to_string(frame)};
  return s;
}

std::vector<datasets::TouchSample> touch_set(int32_t sessions, int32_t frames) {
  std::vector<datasets::TouchSample> out;
  for (int32_t s = 0; s < sessions; ++s)
    for (int32_t f = 0; f < frames; ++f) out.push_back(touch_sample(s, f));
  return out;
}

datasets::GraspEpisode grasp_episode(int32_t object, int32_t grasp) {
  datasets::GraspEpisode e;
  char name[32];
  std::snprintf(name, sizeof name, "object_%02d", object);
  e.object_name = name;
  e.object_id = object;
  e.material.class_id = object % 20;
  e.material.friction = 0.4;
  e.variables.grip_force_n = 5 + grasp;
  e.variables.friction = 0.4;
  e.variables.mass_kg = 0.1 * (object + 1);
  e.variables.com_offset_mm = 3.5;
  e.variables.lift_accel_mps2 = 1.25;
  e.variables.contact_area_mm2[1] = 20.5;
  e.variables.finger_in_contact[1] = grasp % 3 != 0;
  e.is_gripping = grasp % 2 == 0;
  for (int f = 0; f < heads::kFingers; ++f) {
    for (int m = 0; m < heads::kMoments; ++m) {
      e.frames[f][m] =
          smooth_image(20, 28, static_cast<uint64_t>(object * 1000 + grasp * 10 + f * 3 + m));
      e.states[f][m].force_n = m == 0 ? 0 : e.variables.grip_force_n;
      e.states[f][m].in_contact = m != 0;
    }
  }
  for (int m = 0; m < heads::kMoments; ++m)
    e.vision[m] = smooth_image(12, 16, static_cast<uint64_t>(object * 1000 + grasp * 10 + 500 + m));
  return e;
}

ImageDiff image_diff(const datasets::RgbImage& a, const datasets::RgbImage& b) {
  ImageDiff d;
  if (a.height != b.height || a.width != b.width || a.rgb.size() != b.rgb.size() || a.rgb.empty())
    return {255, 255};
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const int32_t diff = std::abs(static_cast<int32_t>(a.rgb[i]) - static_cast<int32_t>(b.rgb[i]));
    sum += diff;
    d.max = std::max(d.max, diff);
  }
  d.mean = sum / static_cast<double>(a.rgb.size());
  return d;
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void write_lines(const std::string& path, const std::vector<std::string>& lines) {
  std::ofstream out(path, std::ios::trunc);
  for (const std::string& l : lines) out << l << "\n";
}

}  // namespace tlvlink::testing
