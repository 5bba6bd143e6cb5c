#include "jpeg_floor.h"

#include <csetjmp>
#include <cstdio>

#include <jpeglib.h>

namespace tlvlink::bench {
namespace {

struct ErrorJump {
  jpeg_error_mgr mgr;
  jmp_buf jump;
};

void on_error(j_common_ptr cinfo) { longjmp(reinterpret_cast<ErrorJump*>(cinfo->err)->jump, 1); }
void quiet(j_common_ptr, int) {}

// Runs `body` on a decompressor reading `jpeg`; false if libjpeg reported an error.
template <typename Body>
bool with_decompressor(std::span<const uint8_t> jpeg, Body body) {
  jpeg_decompress_struct cinfo{};
  ErrorJump err{};
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = on_error;
  err.mgr.emit_message = quiet;
  if (setjmp(err.jump) != 0) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, jpeg.data(), static_cast<unsigned long>(jpeg.size()));
  jpeg_read_header(&cinfo, TRUE);
  body(cinfo);
  jpeg_destroy_decompress(&cinfo);
  return true;
}

}  // namespace

bool entropy_decode(std::span<const uint8_t> jpeg) {
  // Skipping whole iMCU rows makes libjpeg-turbo Huffman-decode them without IDCT, upsampling or
  // colour conversion (jpeg_read_coefficients would also store every coefficient: slower).
  return with_decompressor(jpeg, [](jpeg_decompress_struct& c) {
    c.scale_num = 1;
    c.scale_denom = 8;
    jpeg_start_decompress(&c);
    // Skip all but the last row, then read it: every iMCU row before it must be entropy-decoded
    // to stay in sync (no restart markers); skipping to the very end would decode nothing.
    std::vector<uint8_t> row(static_cast<size_t>(c.output_width) *
                             static_cast<size_t>(c.output_components));
    jpeg_skip_scanlines(&c, c.output_height - 1);
    JSAMPROW r = row.data();
    jpeg_read_scanlines(&c, &r, 1);
    jpeg_finish_decompress(&c);
  });
}

bool cropped_decode(std::span<const uint8_t> jpeg, int32_t scale, int32_t x0, int32_t y0, int32_t w,
                    int32_t h, std::vector<uint8_t>& rgb) {
  return with_decompressor(jpeg, [&](jpeg_decompress_struct& c) {
    c.scale_num = 1;
    c.scale_denom = static_cast<unsigned>(scale);
    c.out_color_space = JCS_RGB;
    jpeg_start_decompress(&c);
    JDIMENSION xoff = static_cast<JDIMENSION>(x0), width = static_cast<JDIMENSION>(w);
    jpeg_crop_scanline(&c, &xoff, &width);
    jpeg_skip_scanlines(&c, static_cast<JDIMENSION>(y0));
    rgb.resize(static_cast<size_t>(c.output_width) * 3);
    for (int32_t r = 0; r < h; ++r) {
      JSAMPROW row = rgb.data();
      jpeg_read_scanlines(&c, &row, 1);
    }
    jpeg_skip_scanlines(&c, c.output_height - c.output_scanline);
    jpeg_finish_decompress(&c);
  });
}

int32_t restart_interval(std::span<const uint8_t> jpeg) {
  int32_t interval = -1;
  with_decompressor(jpeg, [&](jpeg_decompress_struct& c) {
    interval = static_cast<int32_t>(c.restart_interval);
  });
  return interval;
}

}  // namespace tlvlink::bench
