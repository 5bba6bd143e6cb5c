// The frame pipeline: surface -> normal contact -> shear -> membrane spreading -> shading ->
// markers -> camera. All scratch is allocated in create(); render() reuses it.
#include "tlvlink/sim/renderer.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "render/blur.h"
#include "render/camera.h"
#include "render/contact.h"
#include "render/geometry.h"
#include "render/markers.h"
#include "render/model_constants.h"
#include "render/renderer_internal.h"
#include "render/sensor_tables.h"
#include "render/shading.h"
#include "render/shear.h"
#include "render/spreading.h"
#include "render/texture.h"
#include "tlvlink/io/image.h"

namespace tlvlink::sim {
namespace {

using namespace internal;  // NOLINT: the renderer's own internals

class RendererImpl final : public Renderer {
 public:
  RendererImpl(const SensorProfile& profile, uint64_t sensor_seed, Periphery periphery)
      : name_(profile.name),
        profile_(with_name(profile, name_)),
        blur_(profile.width + 2 * periphery.x, profile.height + 2 * periphery.y),
        tables_(build_sensor_tables(profile_, sensor_seed, blur_, periphery)),
        texture_(tables_.grid),
        solver_(tables_.grid),
        spreading_(tables_.grid, profile.gel_thickness_mm),
        markers_(tables_.grid, profile_),
        h_(tables_.grid.pixels()),
        curvature_(tables_.grid.pixels()),
        u_gel_(tables_.grid.pixels()),
        row_scratch_(static_cast<size_t>(tables_.grid.width) * 7) {
    for (auto& d : delta_) d.assign(tables_.grid.pixels(), 0.0f);
  }
  RendererImpl(const RendererImpl&) = delete;  // profile_.name points into name_
  RendererImpl& operator=(const RendererImpl&) = delete;

  Status render(const ContactScene& scene, const RenderOptions& options, uint64_t noise_seed,
                Frame& out) override;
  const std::vector<uint8_t>& background() const override { return tables_.background_u8; }
  const SensorProfile& profile() const override { return profile_; }

 private:
  static SensorProfile with_name(SensorProfile p, const std::string& name) {
    p.name = name;  // the profile's name now points into this renderer
    return p;
  }
  Roi build_surface(const ContactScene& scene, const SurfaceTexture& texture, const Placement& at);
  void clear_dirty();
  void draw_markers(const ShearField& shear, bool contact, Frame& out);

  std::string name_;
  SensorProfile profile_;
  GaussianBlur blur_;
  SensorTables tables_;
  FractalTexture texture_;
  ContactSolver solver_;
  MembraneSpreading spreading_;
  MarkerPainter markers_;
  std::vector<float> h_, curvature_, u_gel_;
  std::array<std::vector<float>, 3> delta_;  // colour change before the camera, 0 outside dirty_
  Roi dirty_;
  std::vector<float> row_scratch_;
  tools::Image jpeg_scratch_;
};

// Object surface (+ dome), its membrane curvature and texture; returns where it has a surface.
Roi RendererImpl::build_surface(const ContactScene& scene, const SurfaceTexture& texture,
                                const Placement& at) {
  const FrameGrid& g = tables_.grid;
  object_height(scene.geometry, at, g, h_.data());
  if (!tables_.dome_height.empty()) {
    for (size_t i = 0; i < h_.size(); ++i) h_[i] += tables_.dome_height[i];
  }
  const Roi surface = surface_bounds(h_.data(), g);
  // The membrane follows the object's shape, not its micro-texture: curvature before texture.
  tension_curvature(h_.data(), g, surface, curvature_.data());
  texture_.add(texture, at.center_x_mm, at.center_y_mm, surface, h_.data(), tables_.view);
  return surface;
}

void RendererImpl::clear_dirty() {
  if (dirty_.empty()) return;
  const size_t w = static_cast<size_t>(tables_.grid.width);
  for (auto& d : delta_) {
    for (int32_t y = dirty_.y0; y < dirty_.y1; ++y) {
      float* row = d.data() + static_cast<size_t>(y) * w;
      std::fill(row + dirty_.x0, row + dirty_.x1, 0.0f);
    }
  }
  dirty_ = {};
}

void RendererImpl::draw_markers(const ShearField& shear, bool contact, Frame& out) {
  const FrameGrid& g = tables_.grid;
  const double s = g.mm_per_px;
  const std::array<const float*, 3> bg = {tables_.background_raw[0].data(),
                                          tables_.background_raw[1].data(),
                                          tables_.background_raw[2].data()};
  const std::array<float*, 3> delta = {delta_[0].data(), delta_[1].data(), delta_[2].data()};
  out.markers.reserve(tables_.marker_rest_mm.size());
  for (const auto& rest : tables_.marker_rest_mm) {
    const auto sh = shear_displacement(shear, rest[0], rest[1]);
    const auto di = contact ? markers_.dilation(rest[0], rest[1]) : std::array<double, 2>{0, 0};
    const double x = rest[0] + sh[0] + di[0], y = rest[1] + sh[1] + di[1];
    // Continuous pixel coordinates with pixel centres at i + 0.5.
    const double cx = x / s + 0.5 * g.width, cy = y / s + 0.5 * g.height;
    markers_.draw(cx, cy, bg, delta, dirty_);
    out.markers.push_back({static_cast<float>(rest[0] / s + 0.5 * g.width - 0.5),
                           static_cast<float>(rest[1] / s + 0.5 * g.height - 0.5),
                           static_cast<float>(cx - 0.5), static_cast<float>(cy - 0.5)});
  }
}

Status RendererImpl::render(const ContactScene& scene, const RenderOptions& options,
                            uint64_t noise_seed, Frame& out) {
  TLV_TRY(validate(scene));
  TLV_TRY(validate(options));
  const FrameGrid& g = tables_.grid;
  const size_t n = g.pixels();
  TLV_ENSURE(scene.geometry.shape != Shape::kHeightMap || scene.geometry.height_map_mm.size() == n,
             ErrorCode::kInvalidArgument,
             "scene.geometry.height_map_mm has %zu values; sensor %.*s needs %d x %d = %zu",
             scene.geometry.height_map_mm.size(), static_cast<int>(profile_.name.size()),
             profile_.name.data(), g.height, g.width, n);
  out.height = g.height;
  out.width = g.width;
  out.rgb.resize(n * 3);
  out.markers.clear();
  out.state = {};
  clear_dirty();

  ContactSolution contact;
  ShearField shear;
  if (scene.geometry.shape != Shape::kNone) {
    const Compliance comp = compliance(profile_, scene.mechanics);
    // The gel takes kappa of the shape but texture_kappa of the texture (contact.h): the
    // texture's heights are scaled so that kappa * scaled = texture_kappa * texture.
    const double texture_kappa = texture_split(profile_, scene.mechanics, scene.texture);
    SurfaceTexture texture = scene.texture;
    if (std::fabs(texture_kappa / comp.kappa - 1) > kTextureSplitTolerance)
      texture.sq_um *= texture_kappa / comp.kappa;
    Placement at{scene.geometry.center_x_mm, scene.geometry.center_y_mm, scene.geometry.angle_deg};
    solver_.prepare(h_.data(), curvature_.data(), comp, build_surface(scene, texture, at));
    const Loading& l = scene.loading;
    const double press = l.force_n >= 0 ? solver_.press_for_force(l.force_n)
                                        : std::min(l.press_mm, comp.max_press_mm);
    contact = solver_.indent(press, u_gel_.data());
    shear = solve_shear(profile_, l, contact);
    if (shear.gross_slip && l.slip_mm > 0) {
      // Gross slip: the object (imprint and texture) has travelled relative to the gel.
      const auto dir = slip_direction(l);
      at.center_x_mm += dir[0] * l.slip_mm;
      at.center_y_mm += dir[1] * l.slip_mm;
      if (shear.rho_torsion > shear.rho_translation) {
        const double turn =
            std::min(l.slip_mm / std::max(shear.contact_radius_mm, 0.5), kMaxSlipTwistRad);
        at.angle_deg += std::copysign(turn, l.torque_nmm) * 180 / std::numbers::pi;
      }
      solver_.prepare(h_.data(), curvature_.data(), comp, build_surface(scene, texture, at));
      contact = solver_.indent(press, u_gel_.data());
      shear.active = contact.in_contact;
      shear.center_x_mm = contact.centroid_x_mm;
      shear.center_y_mm = contact.centroid_y_mm;
      shear.contact_radius_mm = std::sqrt(contact.area_mm2 / std::numbers::pi);
    }
    ContactState& st = out.state;
    st.in_contact = contact.in_contact;
    st.force_n = contact.force_n;
    st.press_mm = press;
    st.max_gel_indentation_mm = contact.max_gel_mm;
    st.kappa = comp.kappa;
    st.texture_kappa = texture_kappa;
    st.contact_area_mm2 = contact.area_mm2;
    st.contact_radius_mm = std::sqrt(contact.area_mm2 / std::numbers::pi);
    st.stick_radius_mm = shear.stick_radius_mm;
    st.slip_ratio = shear.rho;
    st.gross_slip = shear.gross_slip;
    std::array<double, 2> travel{0, 0};
    if (shear.gross_slip) {
      const auto dir = slip_direction(l);
      travel = {dir[0] * l.slip_mm, dir[1] * l.slip_mm};
    }
    const auto stats = marker_shear_stats(shear, tables_.marker_rest_mm, travel);
    st.markers_deviating = stats.deviating;
    st.mean_shear_mm = stats.mean_shear_mm;
  }

  const std::array<float*, 3> delta = {delta_[0].data(), delta_[1].data(), delta_[2].data()};
  if (contact.in_contact) {
    const Roi roi = spreading_.roi(contact);
    const PlaneView z = spreading_.spread(u_gel_.data(), contact.max_gel_mm, roi, blur_);
    ShadingInput in;
    in.z = z;
    in.x0 = roi.x0;
    in.y0 = roi.y0;
    in.mm_per_px = static_cast<float>(g.mm_per_px);
    in.dome_p = tables_.dome_p.empty() ? nullptr : tables_.dome_p.data();
    in.dome_q = tables_.dome_q.empty() ? nullptr : tables_.dome_q.data();
    in.dome_rest = tables_.dome_q.empty() ? nullptr : tables_.dome_rest_ptr.data();
    in.frame_width = g.width;
    in.lights = tables_.lights.data();
    in.light_count = tables_.light_count;
    shade_roi(in, delta, row_scratch_.data());
    dirty_ = roi;
  }
  if (options.markers && profile_.markers) {
    if (contact.in_contact) markers_.prepare_dilation(u_gel_.data(), contact);
    draw_markers(shear, contact.in_contact, out);
  }
  if (!dirty_.empty()) {  // the camera's 5x5 blur, where anything changed
    const int32_t r = kCameraBlurRadiusPx;
    dirty_ = {std::max(0, dirty_.x0 - r), std::max(0, dirty_.y0 - r),
              std::min(g.width, dirty_.x1 + r), std::min(g.height, dirty_.y1 + r)};
    EdgeModes edges;
    edges.left = dirty_.x0 == 0 ? EdgeMode::kReplicate : EdgeMode::kZero;
    edges.top = dirty_.y0 == 0 ? EdgeMode::kReplicate : EdgeMode::kZero;
    edges.right = dirty_.x1 == g.width ? EdgeMode::kReplicate : EdgeMode::kZero;
    edges.bottom = dirty_.y1 == g.height ? EdgeMode::kReplicate : EdgeMode::kZero;
    for (float* d : delta) {
      PlaneView p{d + static_cast<size_t>(dirty_.y0) * static_cast<size_t>(g.width) +
                      static_cast<size_t>(dirty_.x0),
                  dirty_.width(), dirty_.height(), g.width};
      blur_.blur_direct(p, kCameraBlurSigmaPx, kCameraBlurRadiusPx, edges);
    }
  }
  ComposeParams cp;
  cp.led_gain = options.led_gain;
  cp.noise_sigma_dn =
      options.noise_sigma_dn >= 0 ? options.noise_sigma_dn : profile_.noise_sigma_dn;
  cp.noise_seed = noise_seed;
  compose_frame(tables_, {delta[0], delta[1], delta[2]}, dirty_, cp, row_scratch_.data(),
                out.rgb.data());
  if (options.jpeg_quality > 0) {
    TLV_TRY(jpeg_round_trip(out.rgb, g.width, g.height, options.jpeg_quality, options.jpeg_passes,
                            jpeg_scratch_));
  }
  return {};
}

}  // namespace

Result<std::unique_ptr<Renderer>> Renderer::create(const SensorProfile& profile,
                                                   uint64_t sensor_seed) {
  return internal::create_renderer_with_periphery(profile, sensor_seed, {});
}

Result<std::unique_ptr<Renderer>> internal::create_renderer_with_periphery(
    const SensorProfile& profile, uint64_t sensor_seed, Periphery periphery) {
  TLV_TRY(validate(profile));
  TLV_ENSURE(periphery.x >= 0 && periphery.y >= 0 && periphery.x <= 4096 && periphery.y <= 4096,
             ErrorCode::kInvalidArgument, "renderer periphery %d x %d px outside 0..4096",
             periphery.x, periphery.y);
  return std::unique_ptr<Renderer>(new RendererImpl(profile, sensor_seed, periphery));
}

}  // namespace tlvlink::sim
