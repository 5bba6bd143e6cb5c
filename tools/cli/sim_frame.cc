// tlvlink sim frame -o X.ppm: one rendered frame with a chosen sensor, shape and load, for
// looking at (.jpg/.jpeg writes JPEG, anything else binary PPM). --raw Y writes the same frame
// as the sensor's camera emits it (MJPEG .jpg / YUYV .yuyv / RGB .rgb, tlvlink/sim/raw_camera.h).

#include <cstdio>
#include <initializer_list>
#include <map>
#include <span>
#include <string>
#include <utility>

#include "common.h"
#include "sim_commands.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/sim/raw_camera.h"
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
  std::string raw_output;
  int32_t raw_quality = sim::RawOptions{}.jpeg_quality;
  std::string sensor = "gelsight-mini";
  std::string shape = "sphere";
  sim::ContactScene scene;
  sim::RenderOptions options;
  uint64_t seed = 1;
};

bool has_extension(const std::string& path, std::initializer_list<const char*> extensions) {
  for (const char* ext : extensions) {
    const std::string e = ext;
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0)
      return true;
  }
  return false;
}

bool is_jpeg_path(const std::string& path) {
  return has_extension(path, {".jpg", ".jpeg", ".JPG", ".JPEG"});
}

// The raw file's extension must say what it holds: a YUYV frame named .jpg would mislead every
// viewer that opens it.
Status check_raw_path(const std::string& path, sim::RawFormat format) {
  switch (format) {
    case sim::RawFormat::kMjpeg:
      TLV_ENSURE(is_jpeg_path(path), ErrorCode::kInvalidArgument,
                 "--raw %s: this sensor emits MJPEG; name the file .jpg or .jpeg", path.c_str());
      break;
    case sim::RawFormat::kYuyv:
      TLV_ENSURE(has_extension(path, {".yuyv", ".YUYV"}), ErrorCode::kInvalidArgument,
                 "--raw %s: this sensor emits YUYV 4:2:2; name the file .yuyv", path.c_str());
      break;
    case sim::RawFormat::kRgb:
      TLV_ENSURE(has_extension(path, {".rgb", ".RGB"}), ErrorCode::kInvalidArgument,
                 "--raw %s: this sensor emits raw RGB; name the file .rgb", path.c_str());
      break;
  }
  return {};
}

Status write_processed(const std::string& path, const sim::Frame& frame) {
  tools::Image image;
  image.height = frame.height;
  image.width = frame.width;
  image.channels = 3;
  image.pixels = frame.rgb;
  return is_jpeg_path(path) ? tools::write_jpeg(path, image, 95) : tools::write_pnm(path, image);
}

// Renders through RawCamera when --raw is given (its processed frame is the Renderer's, byte for
// byte), else through the Renderer alone.
Status render(const FrameFlags& f, const sim::SensorProfile& profile, sim::Frame& frame,
              sim::RawFrame& raw) {
  if (f.raw_output.empty()) {
    TLV_ASSIGN_OR_RETURN(auto renderer, sim::Renderer::create(profile, f.seed));
    return renderer->render(f.scene, f.options, f.seed, frame);
  }
  sim::RawOptions o;
  o.jpeg_quality = f.raw_quality;
  TLV_ASSIGN_OR_RETURN(auto camera, sim::RawCamera::create(profile, f.seed, o));
  TLV_TRY(check_raw_path(f.raw_output, camera->layout().format));
  TLV_TRY(camera->render(f.scene, f.options, f.seed, raw));
  frame = std::move(raw.processed);
  const sim::RawLayout& l = camera->layout();
  TLV_TRY(tools::write_file(f.raw_output, std::as_bytes(std::span<const uint8_t>(raw.bytes))));
  std::printf("wrote %s (raw %s %dx%d%s, %zu bytes)\n", f.raw_output.c_str(),
              sim::raw_format_name(l.format), l.width, l.height,
              l.transposed ? ", camera orientation" : "", raw.bytes.size());
  return {};
}

int run_frame(FrameFlags f) {
  const char* command = "sim frame";
  if (f.output.empty() && f.raw_output.empty()) {
    return report_error(command, Error(ErrorCode::kInvalidArgument,
                                       "nothing to write: give -o (processed frame), --raw "
                                       "(camera output) or both"));
  }
  auto profile = sim::sensor_profile(f.sensor);
  if (!profile.ok()) return report_error(command, profile.error());
  f.scene.geometry.shape = shape_names().at(f.shape);
  sim::Frame frame;
  sim::RawFrame raw;
  if (Status s = render(f, profile.value(), frame, raw); !s.ok())
    return report_error(command, s.error());
  if (!f.output.empty()) {
    if (Status s = write_processed(f.output, frame); !s.ok())
      return report_error(command, s.error());
  }
  const sim::ContactState& c = frame.state;
  const std::string what = f.output.empty() ? "processed frame" : "wrote " + f.output;
  std::printf(
      "%s (%dx%d, %s): %s, force %.3g N, press %.3g mm, kappa %.3g, area %.3g mm2, "
      "slip ratio %.3g%s\n",
      what.c_str(), frame.width, frame.height, f.sensor.c_str(),
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
      "object and load, and/or the sensor camera's raw output; ranges: tools/sim/REFERENCE.md");
  cmd->add_option("-o,--output", f->output, "Processed frame file (.ppm, or .jpg/.jpeg)");
  cmd->add_option("--raw", f->raw_output,
                  "Also write the frame as the camera emits it: MJPEG .jpg (gelsight-mini "
                  "3280x2464, gelsight-r1.5 320x240) or YUYV .yuyv (digit 320x240, "
                  "digit-640x480; camera orientation, i.e. transposed)");
  cmd->add_option("--raw-quality", f->raw_quality, "MJPEG quality of --raw")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
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
