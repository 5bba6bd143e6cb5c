#include "render/geometry.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "render/model_constants.h"

namespace tlvlink::sim::internal {
namespace {

constexpr auto kNoSurface = static_cast<float>(-kNoSurfaceMm);

// Spherical cap of radius r at squared distance d2 from its axis; no surface beyond the equator.
// sqrt(r^2 - d2) - r is written without cancellation (large radii stay curved in float).
inline float cap(float r, float d2) {
  const float s = r * r - d2;
  return s >= 0 ? -d2 / (std::sqrt(s) + r) : kNoSurface;
}

void height_map(const ObjectGeometry& g, const Placement& at, const FrameGrid& grid, float* h) {
  const int32_t w = grid.width, hh = grid.height;
  const auto dx = static_cast<int32_t>(std::lround(at.center_x_mm / grid.mm_per_px));
  const auto dy = static_cast<int32_t>(std::lround(at.center_y_mm / grid.mm_per_px));
  const size_t n = g.height_map_mm.size();
  for (int32_t y = 0; y < hh; ++y) {
    const int32_t sy = std::clamp(y - dy, 0, hh - 1);
    for (int32_t x = 0; x < w; ++x) {
      const int32_t sx = std::clamp(x - dx, 0, w - 1);
      const size_t i = static_cast<size_t>(sy) * static_cast<size_t>(w) + static_cast<size_t>(sx);
      h[static_cast<size_t>(y * w + x)] = i < n ? g.height_map_mm[i] : 0.0f;
    }
  }
}

}  // namespace

void object_height(const ObjectGeometry& g, const Placement& at, const FrameGrid& grid, float* h) {
  const int32_t w = grid.width, hh = grid.height;
  if (g.shape == Shape::kHeightMap) return height_map(g, at, grid, h);
  if (g.shape == Shape::kFlatPlate || g.shape == Shape::kNone) {
    std::fill(h, h + grid.pixels(), 0.0f);
    return;
  }
  // Radii under 0.75 px are drawn as 0.75 px, so a ball always covers the pixel nearest its
  // centre (at most 0.71 px away): a zero-radius ball is a point contact, not nothing.
  const float r = static_cast<float>(std::max(g.radius_mm, 0.75 * grid.mm_per_px));
  const double a = at.angle_deg * std::numbers::pi / 180;
  const float ca = static_cast<float>(std::cos(a)), sa = static_cast<float>(std::sin(a));
  const float half_len = static_cast<float>(0.5 * g.length_mm);
  const float cone = static_cast<float>(kPointConeSlope);
  // Hyperboloid tip: curvature radius radius_mm (may be 0: a cone), asymptotic slope `cone`.
  const float b = static_cast<float>(g.radius_mm) * cone;
  for (int32_t y = 0; y < hh; ++y) {
    const float Y = static_cast<float>(grid.y_mm(y) - at.center_y_mm);
    float* row = h + static_cast<size_t>(y) * static_cast<size_t>(w);
    switch (g.shape) {
      case Shape::kSphere:
        for (int32_t x = 0; x < w; ++x) {
          const float X = static_cast<float>(grid.x_mm(x) - at.center_x_mm);
          row[x] = cap(r, X * X + Y * Y);
        }
        break;
      case Shape::kCylinder:  // a capsule: distance to the axis segment
        for (int32_t x = 0; x < w; ++x) {
          const float X = static_cast<float>(grid.x_mm(x) - at.center_x_mm);
          const float along = X * ca + Y * sa;
          const float across = -X * sa + Y * ca;
          const float beyond = std::max(0.0f, std::fabs(along) - half_len);
          row[x] = cap(r, across * across + beyond * beyond);
        }
        break;
      case Shape::kBoxEdge:  // face on one side of the edge line, nothing beyond (sharp step)
        for (int32_t x = 0; x < w; ++x) {
          const float X = static_cast<float>(grid.x_mm(x) - at.center_x_mm);
          row[x] = (-X * sa + Y * ca) <= 0 ? 0.0f : kNoSurface;
        }
        break;
      case Shape::kPoint:
        for (int32_t x = 0; x < w; ++x) {
          const float X = static_cast<float>(grid.x_mm(x) - at.center_x_mm);
          const float d2 = X * X + Y * Y;
          const float den = std::sqrt(d2 + b * b) + b;  // 0 only at the tip of a sharp cone
          row[x] = den > 0 ? -cone * d2 / den : 0.0f;
        }
        break;
      default: std::fill(row, row + w, 0.0f); break;
    }
  }
}

Roi surface_bounds(const float* h, const FrameGrid& grid) {
  const auto floor = static_cast<float>(-kSurfaceGapLimitMm);
  Roi r{grid.width, grid.height, 0, 0};
  for (int32_t y = 0; y < grid.height; ++y) {
    const float* row = h + static_cast<size_t>(y) * static_cast<size_t>(grid.width);
    int32_t first = 0;
    while (first < grid.width && !(row[first] > floor)) ++first;
    if (first == grid.width) continue;
    int32_t last = grid.width - 1;
    while (!(row[last] > floor)) --last;
    r = {std::min(r.x0, first), std::min(r.y0, y), std::max(r.x1, last + 1), y + 1};
  }
  return r.empty() ? Roi{} : r;
}

void tension_curvature(const float* h0, const FrameGrid& grid, Roi roi, float* curvature) {
  const int32_t w = grid.width, hh = grid.height;
  const auto cap_d = static_cast<float>(kTensionMaxSlope * grid.mm_per_px);
  // g_n - g = h - h_n, clamped; a missing neighbour (frame border) contributes 0.
  auto diff = [cap_d](float centre, float neighbour) {
    return std::min(std::max(centre - neighbour, -cap_d), cap_d);
  };
  for (int32_t y = roi.y0; y < roi.y1; ++y) {
    const float* r = h0 + static_cast<size_t>(y) * static_cast<size_t>(w);
    const float* u = h0 + static_cast<size_t>(std::max(y - 1, 0)) * static_cast<size_t>(w);
    const float* d = h0 + static_cast<size_t>(std::min(y + 1, hh - 1)) * static_cast<size_t>(w);
    float* out = curvature + static_cast<size_t>(y) * static_cast<size_t>(w);
    for (int32_t x = std::max(roi.x0, 1); x < std::min(roi.x1, w - 1); ++x) {
      const float c = r[x];
      const float s = diff(c, r[x - 1]) + diff(c, r[x + 1]) + diff(c, u[x]) + diff(c, d[x]);
      out[x] = std::max(0.0f, s);
    }
    for (int32_t x : {0, w - 1}) {
      if (x < roi.x0 || x >= roi.x1) continue;
      const float c = r[x];
      const float s = diff(c, r[std::max(x - 1, 0)]) + diff(c, r[std::min(x + 1, w - 1)]) +
                      diff(c, u[x]) + diff(c, d[x]);
      out[x] = std::max(0.0f, s);
    }
  }
}

}  // namespace tlvlink::sim::internal
