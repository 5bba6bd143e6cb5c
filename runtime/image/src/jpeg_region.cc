#include "jpeg_region.h"

#include <csetjmp>
#include <cstdio>

#include <jpeglib.h>

#include "tlvlink/image/decode_budget.h"

namespace tlvlink::image::internal {
namespace {

struct ErrorJump {
  jpeg_error_mgr mgr;
  jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void on_error(j_common_ptr c) {
  auto* e = reinterpret_cast<ErrorJump*>(c->err);
  (*c->err->format_message)(c, e->message);
  longjmp(e->jump, 1);
}

// Warnings (a stream that ends early, corrupt data libjpeg would paper over with grey) are
// errors: a damaged camera frame must not become a prediction.
void on_message(j_common_ptr c, int level) {
  if (level < 0) on_error(c);
}

struct Outcome {
  int width = 0, height = 0;  // the header's size, when it was read
  JDIMENSION x = 0, w = 0;    // the region's columns as the decoder set them
  bool ok = false;
};

// Only plain C objects live in this frame: longjmp skips no destructor.
Outcome run(const uint8_t* data, size_t size, int32_t scale, const Region& want, uint8_t* out,
            size_t row_bytes, bool header_only, ErrorJump& err) {
  Outcome o;
  jpeg_decompress_struct c{};
  c.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = on_error;
  err.mgr.emit_message = on_message;
  if (setjmp(err.jump) != 0) {
    jpeg_destroy_decompress(&c);
    return o;
  }
  jpeg_create_decompress(&c);
  jpeg_mem_src(&c, data, static_cast<unsigned long>(size));
  jpeg_read_header(&c, TRUE);
  o.width = static_cast<int>(c.image_width);
  o.height = static_cast<int>(c.image_height);
  if (header_only) {
    jpeg_destroy_decompress(&c);
    o.ok = true;
    return o;
  }
  c.scale_num = 1;
  c.scale_denom = static_cast<unsigned>(scale);
  c.out_color_space = JCS_RGB;
  jpeg_start_decompress(&c);
  o.x = static_cast<JDIMENSION>(want.x);
  o.w = static_cast<JDIMENSION>(want.width);
  jpeg_crop_scanline(&c, &o.x, &o.w);
  if (want.y > 0) jpeg_skip_scanlines(&c, static_cast<JDIMENSION>(want.y));
  for (int32_t r = 0; r < want.height; ++r) {
    JSAMPROW row = out + static_cast<size_t>(r) * row_bytes;
    if (jpeg_read_scanlines(&c, &row, 1) != 1) on_error(reinterpret_cast<j_common_ptr>(&c));
  }
  // The rows below the region: read through the end so a truncated stream is still caught.
  if (c.output_scanline < c.output_height) {
    jpeg_skip_scanlines(&c, c.output_height - c.output_scanline);
  }
  jpeg_finish_decompress(&c);
  jpeg_destroy_decompress(&c);
  o.ok = true;
  return o;
}

}  // namespace

Status JpegRegionDecoder::init(int32_t width, int32_t height, int32_t scale, Region want) {
  width_ = width;
  height_ = height;
  scale_ = scale;
  want_ = want;
  // Widening the start to an iMCU boundary adds at most one iMCU (16 px at full scale) of columns.
  const int32_t widen = 16 / scale + 1;
  pixels_.assign(static_cast<size_t>(want.width + widen) * static_cast<size_t>(want.height) * 3, 0);
  got_ = want;
  return {};
}

Status JpegRegionDecoder::decode(std::span<const uint8_t> jpeg, const char* what) {
  TLV_ENSURE(!jpeg.empty(), ErrorCode::kFormat, "%s: empty JPEG data (0 bytes)", what);
  ErrorJump err{};
  const int32_t widen = 16 / scale_ + 1;
  const size_t row_bytes = static_cast<size_t>(want_.width + widen) * 3;
  // The header first: a frame of another size must not be decoded into this region's buffers.
  Outcome h = run(jpeg.data(), jpeg.size(), scale_, want_, nullptr, 0, true, err);
  TLV_ENSURE(h.ok, ErrorCode::kFormat, "%s: unreadable or incomplete JPEG header (%zu bytes): %s",
             what, jpeg.size(), err.message);
  TLV_ENSURE(h.width == width_ && h.height == height_, ErrorCode::kFormat,
             "%s: JPEG frame is %dx%d, expected %dx%d", what, h.width, h.height, width_, height_);
  TLV_TRY(check_decode_budget(h.width, h.height, 3, jpeg.size(), kJpegMaxRatio, "JPEG", what));
  Outcome o = run(jpeg.data(), jpeg.size(), scale_, want_, pixels_.data(), row_bytes, false, err);
  TLV_ENSURE(o.ok, ErrorCode::kFormat, "%s: truncated or corrupt JPEG (%dx%d, %zu bytes): %s", what,
             width_, height_, jpeg.size(), err.message);
  got_ = {static_cast<int32_t>(o.x), want_.y, static_cast<int32_t>(o.w), want_.height};
  return {};
}

}  // namespace tlvlink::image::internal
