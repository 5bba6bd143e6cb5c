// Allocating JPEG conveniences for host tools: one decoder and encoder per thread, worth reusing
// across the thousands of frames a dataset run encodes.
#include "tlvlink/image/jpeg.h"

namespace tlvlink::image {
namespace {

JpegDecoder& thread_decoder() {
  thread_local JpegDecoder decoder;
  return decoder;
}

JpegEncoder& thread_encoder() {
  thread_local JpegEncoder encoder;
  return encoder;
}

}  // namespace

Result<std::vector<uint8_t>> encode_jpeg(const Image& image, int32_t quality, bool full_chroma) {
  TLV_ENSURE(image.channels == 1 || image.channels == 3, ErrorCode::kInvalidArgument,
             "JPEG encode: %d channels (expected 1 or 3)", image.channels);
  const size_t need = static_cast<size_t>(image.width) * static_cast<size_t>(image.height) *
                      static_cast<size_t>(image.channels);
  TLV_ENSURE(image.pixels.size() == need, ErrorCode::kInvalidArgument,
             "JPEG encode: %zu pixel bytes for %dx%dx%d (expected %zu)", image.pixels.size(),
             image.width, image.height, image.channels, need);
  TLV_ASSIGN_OR_RETURN(const std::span<const uint8_t> bytes,
                       thread_encoder().encode(image.view(), quality,
                                               image.channels == 1 ? JpegEncoder::Subsampling::kGray
                                               : full_chroma       ? JpegEncoder::Subsampling::k444
                                                             : JpegEncoder::Subsampling::k420));
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

Result<Image> decode_jpeg(std::span<const uint8_t> bytes, const std::string& name,
                          int32_t scale_denominator) {
  TLV_ENSURE(jpeg_scale_supported(scale_denominator), ErrorCode::kInvalidArgument,
             "%s: JPEG scale 1/%d not offered (1, 2, 4 or 8)", name.c_str(), scale_denominator);
  JpegDecoder& decoder = thread_decoder();
  TLV_ASSIGN_OR_RETURN(const JpegHeader h, decoder.read_header(bytes, name.c_str()));
  Image image;
  image.width = jpeg_scaled_size(h.width, scale_denominator);
  image.height = jpeg_scaled_size(h.height, scale_denominator);
  image.channels = 3;
  image.pixels.resize(static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3);
  TLV_TRY(decoder.decode_rgb(bytes, scale_denominator, image.pixels.data(), image.pixels.size(), 0,
                             name.c_str()));
  return image;
}

}  // namespace tlvlink::image
