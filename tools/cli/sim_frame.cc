// tlvlink sim frame -o X.ppm: one rendered frame with a chosen sensor, shape and load, for
// looking at (.jpg/.jpeg writes JPEG, anything else binary PPM).

#include <cstdio>
#include <map>
#include <string>

#include "cli/common.h"
#include "cli/sim_commands.h"
#include "io/jpeg.h"
#include "io/pnm.h"
#include "tlvlink/sim/renderer.h"

namespace tlvlink::cli {
namespace {

const std::map<std::string, sim::Shape>& shape_names() {
  static const std::map<std::string, sim::Shape> names = {
      {"none", sim::Shape::kNone},         {"sphere", sim::Shape::kSphere},
      {"cylinder", sim::Shape::kCylinder}, {"flat", sim::Shape::kFlatPlate},
      {"edge", sim::Shape::kBoxEdge},      {"point", sim::Shape::kPoint}};
  return names;
}

struct FrameFlags {
  std::string output;
  std::string sensor = "gelsight-mini";
  std::string shape = "sphere";
  sim::ContactScene scene;
  sim::RenderOptions options;
  uint64_t seed = 1;
};

bool is_jpeg_path(const std::string& path) {
  for (const char* ext : {".jpg", ".jpeg", ".JPG", ".JPEG"}) {
    const std::string e = ext;
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0)
      return true;
  }
  return false;
}

int run_frame(FrameFlags f) {
  const char* command = "sim frame";
  auto profile = sim::sensor_profile(f.sensor);
  if (!profile.ok()) return report_error(command, profile.error());
  f.scene.geometry.shape = shape_names().at(f.shape);
  auto renderer = sim::Renderer::create(profile.value(), f.seed);
  if (!renderer.ok()) return report_error(command, renderer.error());
  sim::Frame frame;
  if (Status s = (*renderer)->render(f.scene, f.options, f.seed, frame); !s.ok())
    return report_error(command, s.error());
  tools::Image image;
  image.height = frame.height;
  image.width = frame.width;
  image.channels = 3;
  image.pixels = frame.rgb;
  const Status written = is_jpeg_path(f.output) ? tools::write_jpeg(f.output, image, 95)
                                                : tools::write_pnm(f.output, image);
  if (!written.ok()) return report_error(command, written.error());
  const sim::ContactState& c = frame.state;
  std::printf(
      "wrote %s (%dx%d, %s): %s, force %.3g N, press %.3g mm, kappa %.3g, area %.3g mm2, "
      "slip ratio %.3g%s\n",
      f.output.c_str(), frame.width, frame.height, f.sensor.c_str(),
      c.in_contact ? "in contact" : "no contact", c.force_n, c.press_mm, c.kappa,
      c.contact_area_mm2, c.slip_ratio, c.gross_slip ? " (gross slip)" : "");
  return kExitOk;
}

}  // namespace

void add_sim_frame_command(CLI::App& sim, int& exit_code) {
  auto f = std::make_shared<FrameFlags>();
  CLI::App* cmd = sim.add_subcommand(
      "frame",
      "Render one GelSight frame (PPM, or JPEG q95 for .jpg) with a chosen sensor, "
      "object and load; ranges: tools/sim/README.md");
  cmd->add_option("-o,--output", f->output, "Output file (.ppm, or .jpg/.jpeg)")->required();
  cmd->add_option("--sensor", f->sensor,
                  "Sensor profile: gelsight-mini, digit, digit-640x480, gelsight-r1.5")
      ->capture_default_str();
  std::vector<std::string> shapes;
  for (const auto& [name, shape] : shape_names()) shapes.push_back(name);
  cmd->add_option("--shape", f->shape, "Object shape")
      ->check(CLI::IsMember(shapes))
      ->capture_default_str();
  sim::ContactScene& s = f->scene;
  cmd->add_option("--radius", s.geometry.radius_mm, "Sphere/cylinder/point radius, mm")
      ->capture_default_str();
  cmd->add_option("--length", s.geometry.length_mm, "Cylinder length, mm")->capture_default_str();
  cmd->add_option("--angle", s.geometry.angle_deg, "Cylinder axis / edge direction, degrees")
      ->capture_default_str();
  cmd->add_option("--x", s.geometry.center_x_mm, "Offset from the gel centre, mm")
      ->capture_default_str();
  cmd->add_option("--y", s.geometry.center_y_mm, "Offset from the gel centre, mm")
      ->capture_default_str();
  cmd->add_option("--force", s.loading.force_n, "Normal force, N (< 0: use --press)")
      ->capture_default_str();
  cmd->add_option("--press", s.loading.press_mm, "Press depth, mm (with --force -1)")
      ->capture_default_str();
  cmd->add_option("--shear-x", s.loading.shear_x_n, "Tangential load, N")->capture_default_str();
  cmd->add_option("--shear-y", s.loading.shear_y_n, "Tangential load, N")->capture_default_str();
  cmd->add_option("--torque", s.loading.torque_nmm, "Torque about the normal, N mm")
      ->capture_default_str();
  cmd->add_option("--friction", s.loading.friction, "Friction coefficient")->capture_default_str();
  cmd->add_option("--slip", s.loading.slip_mm, "Gross-slip travel, mm")->capture_default_str();
  cmd->add_option("--modulus", s.mechanics.modulus_pa, "Object Young's modulus, Pa")
      ->capture_default_str();
  cmd->add_option("--poisson", s.mechanics.poisson, "Object Poisson ratio")->capture_default_str();
  cmd->add_option("--sq-um", s.texture.sq_um, "Surface RMS roughness, um")->capture_default_str();
  cmd->add_option("--correlation-length", s.texture.correlation_length_mm,
                  "Texture correlation length, mm")
      ->capture_default_str();
  cmd->add_option("--hurst", s.texture.hurst, "Texture Hurst exponent")->capture_default_str();
  cmd->add_flag("--markers", f->options.markers, "Draw the marker grid");
  cmd->add_option("--led-gain", f->options.led_gain, "LED gain (0 = black, > 1 saturates)")
      ->capture_default_str();
  cmd->add_option("--noise", f->options.noise_sigma_dn, "Camera noise sigma, DN (< 0: profile's)")
      ->capture_default_str();
  cmd->add_option("--jpeg-quality", f->options.jpeg_quality,
                  "JPEG round trip inside the camera model (0 = none)")
      ->capture_default_str();
  cmd->add_option("-s,--seed", f->seed, "Sensor and noise seed")->capture_default_str();
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_frame(*f); });
}

}  // namespace tlvlink::cli
