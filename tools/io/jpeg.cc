#include "io/jpeg.h"

#include <turbojpeg.h>

#include <memory>

#include "io/file.h"

namespace tlvlink::tools {
namespace {

// Largest JPEG file read_jpeg accepts: an 8 MP MJPEG frame is a few MB even at q=100.
constexpr size_t kMaxJpegFileBytes = size_t{256} << 20;

// One compressor and one decompressor per thread: tjInit* allocates libjpeg state, which is
// worth reusing across the thousands of frames a dataset run encodes.
struct Handles {
  tjhandle compress = nullptr;
  tjhandle decompress = nullptr;
  ~Handles() {
    if (compress) tjDestroy(compress);
    reset_decompress();
  }
  // libjpeg-turbo 2.1 leaves a handle that failed mid-header unusable (the next valid image
  // reads as 0x0), so one bad file would spoil the next: start afresh after any error.
  void reset_decompress() {
    if (decompress) tjDestroy(decompress);
    decompress = nullptr;
  }
};

Handles& thread_handles() {
  thread_local Handles handles;
  return handles;
}

struct TjFree {
  void operator()(unsigned char* p) const { tjFree(p); }
};

}  // namespace

Result<std::vector<uint8_t>> encode_jpeg(const Image& image, int32_t quality) {
  TLV_ENSURE(quality >= 1 && quality <= 100, ErrorCode::kInvalidArgument,
             "JPEG quality %d outside 1..100", quality);
  TLV_ENSURE(image.channels == 1 || image.channels == 3, ErrorCode::kInvalidArgument,
             "JPEG encode: %d channels (expected 1 or 3)", image.channels);
  TLV_ENSURE(image.width >= 1 && image.height >= 1 && image.width <= kMaxJpegSide &&
                 image.height <= kMaxJpegSide,
             ErrorCode::kInvalidArgument, "JPEG encode: size %dx%d outside 1..%d", image.width,
             image.height, kMaxJpegSide);
  const size_t need = static_cast<size_t>(image.width) * static_cast<size_t>(image.height) *
                      static_cast<size_t>(image.channels);
  TLV_ENSURE(image.pixels.size() == need, ErrorCode::kInvalidArgument,
             "JPEG encode: %zu pixel bytes for %dx%dx%d (expected %zu)", image.pixels.size(),
             image.width, image.height, image.channels, need);
  Handles& h = thread_handles();
  if (!h.compress) h.compress = tjInitCompress();
  TLV_ENSURE(h.compress != nullptr, ErrorCode::kOutOfMemory, "JPEG encode: tjInitCompress failed");
  const bool rgb = image.channels == 3;
  unsigned char* out = nullptr;
  unsigned long out_size = 0;
  const int rc = tjCompress2(h.compress, image.pixels.data(), image.width, 0, image.height,
                             rgb ? TJPF_RGB : TJPF_GRAY, &out, &out_size,
                             rgb ? TJSAMP_420 : TJSAMP_GRAY, quality, 0);
  std::unique_ptr<unsigned char, TjFree> owned(out);
  TLV_ENSURE(rc == 0, ErrorCode::kFormat, "JPEG encode %dx%d: %s", image.width, image.height,
             tjGetErrorStr2(h.compress));
  return std::vector<uint8_t>(out, out + out_size);
}

Result<Image> decode_jpeg(std::span<const uint8_t> bytes, const std::string& name,
                          int32_t scale_denominator) {
  TLV_ENSURE(scale_denominator == 1 || scale_denominator == 2 || scale_denominator == 4 ||
                 scale_denominator == 8,
             ErrorCode::kInvalidArgument, "%s: JPEG scale 1/%d not offered (1, 2, 4 or 8)",
             name.c_str(), scale_denominator);
  TLV_ENSURE(!bytes.empty(), ErrorCode::kFormat, "%s: empty JPEG data", name.c_str());
  Handles& h = thread_handles();
  if (!h.decompress) h.decompress = tjInitDecompress();
  TLV_ENSURE(h.decompress != nullptr, ErrorCode::kOutOfMemory, "%s: tjInitDecompress failed",
             name.c_str());
  int width = 0, height = 0, subsamp = 0, colorspace = 0;
  // tj* take a non-const pointer for historical reasons; they do not write to the input.
  auto* data = const_cast<unsigned char*>(bytes.data());
  if (tjDecompressHeader3(h.decompress, data, bytes.size(), &width, &height, &subsamp,
                          &colorspace) != 0) {
    const Error e = Error::make(ErrorCode::kFormat, "%s: not a readable JPEG (%zu bytes): %s",
                                name.c_str(), bytes.size(), tjGetErrorStr2(h.decompress));
    h.reset_decompress();
    return e;
  }
  TLV_ENSURE(width >= 1 && height >= 1 && width <= kMaxJpegSide && height <= kMaxJpegSide,
             ErrorCode::kFormat, "%s: JPEG size %dx%d outside 1..%d", name.c_str(), width, height,
             kMaxJpegSide);
  const tjscalingfactor factor{1, scale_denominator};
  Image image;
  image.width = TJSCALED(width, factor);
  image.height = TJSCALED(height, factor);
  image.channels = 3;
  image.pixels.resize(static_cast<size_t>(image.width) * static_cast<size_t>(image.height) * 3);
  // STOPONWARNING: a truncated or damaged stream is reported, not silently padded with grey.
  if (tjDecompress2(h.decompress, data, bytes.size(), image.pixels.data(), image.width, 0,
                    image.height, TJPF_RGB, TJFLAG_STOPONWARNING) != 0) {
    const Error e = Error::make(ErrorCode::kFormat, "%s: corrupt JPEG (%dx%d, %zu bytes): %s",
                                name.c_str(), width, height, bytes.size(),
                                tjGetErrorStr2(h.decompress));
    h.reset_decompress();
    return e;
  }
  return image;
}

Result<Image> read_jpeg(const std::string& path, int32_t scale_denominator) {
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, read_file(path, kMaxJpegFileBytes));
  return decode_jpeg({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, path,
                     scale_denominator);
}

Status write_jpeg(const std::string& path, const Image& image, int32_t quality) {
  auto encoded = encode_jpeg(image, quality);
  if (!encoded.ok()) return encoded.error().with_context("%s", path.c_str());
  return write_file(path, std::as_bytes(std::span<const uint8_t>(encoded.value())));
}

}  // namespace tlvlink::tools
