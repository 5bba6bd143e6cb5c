#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "blur.h is internal to tools/sim: include its public headers instead"
#endif
// Separable Gaussian blur of a float plane (or a rectangle of one) with per-side edge modes.
// Small sigmas use a direct kernel; sigma >= kRecursiveMinSigma uses Deriche's fourth-order
// recursive Gaussian (cost independent of sigma) along columns, with a transpose for the rows,
// so both passes run over contiguous rows and vectorise.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tlvlink::sim::internal {

struct PlaneView {
  float* data = nullptr;
  int32_t width = 0, height = 0;
  ptrdiff_t stride = 0;  // floats between rows
  float* row(int32_t y) const { return data + y * stride; }
};

// What lies beyond each side: zeros (the rectangle is inside a zero field) or the edge value
// repeated (the side is the frame border; the gel continues beyond the view).
enum class EdgeMode : uint8_t { kZero, kReplicate };
struct EdgeModes {
  EdgeMode left = EdgeMode::kReplicate, right = EdgeMode::kReplicate;
  EdgeMode top = EdgeMode::kReplicate, bottom = EdgeMode::kReplicate;
};

inline constexpr double kRecursiveMinSigma = 2.0;
inline constexpr int32_t kMaxDirectRadius = 8;

class GaussianBlur {
 public:
  // Allocates scratch for planes up to max_width x max_height (the only allocation).
  GaussianBlur(int32_t max_width, int32_t max_height);

  // Blurs `plane` in place with standard deviation sigma_px (> 0).
  void blur(PlaneView plane, double sigma_px, EdgeModes edges);
  // Direct kernel of the given radius (<= kMaxDirectRadius), e.g. the camera's 5x5 (radius 2).
  void blur_direct(PlaneView plane, double sigma_px, int32_t radius, EdgeModes edges);

 private:
  void recursive_columns(PlaneView plane, double sigma_px, EdgeMode top, EdgeMode bottom);
  void direct_columns(PlaneView src, PlaneView dst, const float* kernel, int32_t radius,
                      EdgeMode top, EdgeMode bottom);
  void direct_rows(PlaneView src, PlaneView dst, const float* kernel, int32_t radius, EdgeMode left,
                   EdgeMode right);

  std::vector<float> temp_;                   // max_width * max_height
  std::vector<float> transposed_;             // max_width * max_height
  std::vector<float> line_;                   // one padded line
  static constexpr size_t kScratchRows = 14;  // recursive filter: edges + two 5-row rings
  std::vector<float> rows_;
  std::vector<float> zero_row_;
};

// dst (height x width of src, transposed) = src^T.
void transpose(PlaneView src, PlaneView dst);

}  // namespace tlvlink::sim::internal
