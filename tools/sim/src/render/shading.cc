#include "render/shading.h"

#include <algorithm>
#include <cmath>

#include "render/model_constants.h"

namespace tlvlink::sim::internal {
namespace {

constexpr float kKd = static_cast<float>(kDiffuse);
constexpr float kKs = static_cast<float>(kSpecular);
constexpr float kSlopeCap = static_cast<float>(kMaxSlope);

inline float term(const LightModel& l, float nx, float ny, float nz) {
  const float ndotl = nx * l.lx + ny * l.ly + nz * l.lz;
  const float rv = std::max(0.0f, 2.0f * ndotl * nz - l.lz);
  const float rv2 = rv * rv;
  return kKd * std::max(0.0f, ndotl) + kKs * rv2 * rv2 * rv;  // alpha = 5
}

// Unit normal of slopes (p, q) after the |grad| <= 2.5 clamp.
inline void normal(float p, float q, float& nx, float& ny, float& nz) {
  const float k = kSlopeCap / std::sqrt(std::max(p * p + q * q, kSlopeCap * kSlopeCap));
  p *= k;
  q *= k;
  const float inv = 1.0f / std::sqrt(1.0f + p * p + q * q);
  nx = -p * inv;
  ny = -q * inv;
  nz = inv;
}

// One light's contribution over a row; restrict-qualified so the loop vectorises.
[[gnu::noinline]] void accumulate_light(const LightModel& l, const float* __restrict nx,
                                        const float* __restrict ny, const float* __restrict nz,
                                        const float* __restrict rest, int32_t w,
                                        float* __restrict o0, float* __restrict o1,
                                        float* __restrict o2) {
  const float a0 = l.amp[0], a1 = l.amp[1], a2 = l.amp[2];
  const float lx = l.lx, ly = l.ly, lz = l.lz;
  for (int32_t x = 0; x < w; ++x) {
    const float ndotl = nx[x] * lx + ny[x] * ly + nz[x] * lz;
    float rv = 2.0f * ndotl * nz[x] - lz;
    rv = rv > 0.0f ? rv : 0.0f;
    const float rv2 = rv * rv;
    const float diffuse = ndotl > 0.0f ? ndotl : 0.0f;
    const float t = kKd * diffuse + kKs * rv2 * rv2 * rv - rest[x];
    o0[x] += a0 * t;
    o1[x] += a1 * t;
    o2[x] += a2 * t;
  }
}

// Unit normals of a row of slopes with the |grad| <= 2.5 clamp, branch-free.
[[gnu::noinline]] void row_normals(const float* __restrict px, const float* __restrict qy,
                                   int32_t w, float* __restrict nx, float* __restrict ny,
                                   float* __restrict nz) {
  const float cap2 = kSlopeCap * kSlopeCap;
  for (int32_t x = 0; x < w; ++x) {
    float p = px[x], q = qy[x];
    const float g2 = p * p + q * q;
    const float k = kSlopeCap / std::sqrt(std::max(g2, cap2));  // 1 below the cap
    p *= k;
    q *= k;
    const float inv = 1.0f / std::sqrt(1.0f + p * p + q * q);
    nx[x] = -p * inv;
    ny[x] = -q * inv;
    nz[x] = inv;
  }
}

}  // namespace

float shading_term(const LightModel& light, float nx, float ny, float nz) {
  return term(light, nx, ny, nz);
}

float shading_term_for_slopes(const LightModel& light, float p, float q) {
  float nx, ny, nz;
  normal(p, q, nx, ny, nz);
  return term(light, nx, ny, nz);
}

std::array<float, 3> shading_delta(const LightModel* lights, int32_t count, float p, float q,
                                   float p0, float q0) {
  float nx, ny, nz, mx, my, mz;
  normal(p, q, nx, ny, nz);
  normal(p0, q0, mx, my, mz);
  std::array<float, 3> out{};
  for (int32_t i = 0; i < count; ++i) {
    const float t = term(lights[i], nx, ny, nz) - term(lights[i], mx, my, mz);
    for (int c = 0; c < 3; ++c)
      out[static_cast<size_t>(c)] += lights[i].amp[static_cast<size_t>(c)] * t;
  }
  return out;
}

void shade_roi(const ShadingInput& in, std::array<float*, 3> out, float* row_scratch) {
  const int32_t w = in.z.width, h = in.z.height;
  if (w <= 0 || h <= 0) return;
  const float inv2s = 0.5f / in.mm_per_px;
  float* nx = row_scratch;
  float* ny = nx + w;
  float* nz = ny + w;
  float* rest = nz + w;  // shading term of the rest normal (dome), per light in turn
  float* px = rest + w;
  float* qy = px + w;
  for (int32_t y = 0; y < h; ++y) {
    const float* zr = in.z.row(y);
    const float* zu = in.z.row(std::max(y - 1, 0));
    const float* zd = in.z.row(std::min(y + 1, h - 1));
    // Central differences; one-sided at the ROI border (where z is ~0 anyway).
    const float sy = (y == 0 || y == h - 1) ? (h > 1 ? 2 * inv2s : 0.0f) : inv2s;
    for (int32_t x = 0; x < w; ++x) qy[x] = (zd[x] - zu[x]) * sy;
    if (w > 1) {
      px[0] = (zr[1] - zr[0]) * 2 * inv2s;
      px[w - 1] = (zr[w - 1] - zr[w - 2]) * 2 * inv2s;
    } else {
      px[0] = 0;
    }
    for (int32_t x = 1; x < w - 1; ++x) px[x] = (zr[x + 1] - zr[x - 1]) * inv2s;
    const size_t frame_row = static_cast<size_t>(in.y0 + y) * static_cast<size_t>(in.frame_width) +
                             static_cast<size_t>(in.x0);
    const float* p0 = in.dome_p ? in.dome_p + frame_row : nullptr;
    const float* q0 = in.dome_q ? in.dome_q + frame_row : nullptr;
    if (p0) {
      for (int32_t x = 0; x < w; ++x) {
        px[x] += p0[x];
        qy[x] += q0[x];
      }
    }
    row_normals(px, qy, w, nx, ny, nz);
    float* o0 = out[0] + frame_row;
    float* o1 = out[1] + frame_row;
    float* o2 = out[2] + frame_row;
    for (int32_t x = 0; x < w; ++x) o0[x] = o1[x] = o2[x] = 0.0f;
    for (int32_t i = 0; i < in.light_count; ++i) {
      const LightModel& l = in.lights[i];
      const float* rest_i = in.dome_rest ? in.dome_rest[i] + frame_row : rest;
      if (!in.dome_rest) {
        const float flat = kKd * std::max(0.0f, l.lz) + kKs * l.spec0;
        for (int32_t x = 0; x < w; ++x) rest[x] = flat;
      }
      accumulate_light(l, nx, ny, nz, rest_i, w, o0, o1, o2);
    }
  }
}

}  // namespace tlvlink::sim::internal
