#include "tlvlink/io/pnm.h"

#include <cstring>
#include <string_view>

#include "tlvlink/image/decode_budget.h"
#include "tlvlink/io/file.h"

namespace tlvlink::tools {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

class HeaderReader {
 public:
  HeaderReader(std::span<const std::byte> bytes, const std::string& name)
      : s_(reinterpret_cast<const char*>(bytes.data()), bytes.size()), name_(name) {}

  // Skips whitespace and comments, then reads a decimal field.
  Result<int32_t> number(const char* what) {
    for (;;) {
      while (pos_ < s_.size() && is_space(s_[pos_])) ++pos_;
      if (pos_ < s_.size() && s_[pos_] == '#') {
        while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
        continue;
      }
      break;
    }
    TLV_ENSURE(pos_ < s_.size(), ErrorCode::kFormat, "%s: truncated header (no %s)", name_.c_str(),
               what);
    TLV_ENSURE(s_[pos_] >= '0' && s_[pos_] <= '9', ErrorCode::kFormat,
               "%s: header %s is not a number (offset %zu)", name_.c_str(), what, pos_);
    int64_t v = 0;
    while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') {
      v = v * 10 + (s_[pos_++] - '0');
      TLV_ENSURE(v <= 1000000, ErrorCode::kFormat, "%s: header %s is absurdly large", name_.c_str(),
                 what);
    }
    TLV_ENSURE(pos_ < s_.size(), ErrorCode::kFormat, "%s: truncated header (after %s)",
               name_.c_str(), what);
    TLV_ENSURE(is_space(s_[pos_]), ErrorCode::kFormat,
               "%s: header %s must be followed by whitespace", name_.c_str(), what);
    return static_cast<int32_t>(v);
  }
  // Exactly one whitespace byte separates maxval from the pixels.
  size_t data_offset() const { return pos_ + 1; }

 private:
  std::string_view s_;
  const std::string& name_;
  size_t pos_ = 2;  // after the magic
};

}  // namespace

Result<Image> parse_pnm(std::span<const std::byte> bytes, const std::string& name) {
  TLV_ENSURE(bytes.size() >= 2, ErrorCode::kFormat, "%s: too short for a PPM/PGM file",
             name.c_str());
  const char m0 = static_cast<char>(bytes[0]), m1 = static_cast<char>(bytes[1]);
  TLV_ENSURE(
      m0 == 'P' && (m1 == '6' || m1 == '5'), ErrorCode::kFormat,
      "%s: not a binary PPM/PGM (magic '%c%c'; expected P6 or P5; ASCII P3/P2 are not supported)",
      name.c_str(), m0 >= 0x20 && m0 < 0x7f ? m0 : '?', m1 >= 0x20 && m1 < 0x7f ? m1 : '?');
  HeaderReader header(bytes, name);
  Image img;
  img.channels = m1 == '6' ? 3 : 1;
  TLV_ASSIGN_OR_RETURN(img.width, header.number("width"));
  TLV_ASSIGN_OR_RETURN(img.height, header.number("height"));
  TLV_ASSIGN_OR_RETURN(const int32_t maxval, header.number("maxval"));
  TLV_ENSURE(img.width >= 1 && img.height >= 1 && img.width <= kMaxImageSide &&
                 img.height <= kMaxImageSide,
             ErrorCode::kFormat, "%s: size %dx%d outside 1..%d", name.c_str(), img.width,
             img.height, kMaxImageSide);
  TLV_ENSURE(maxval == 255, ErrorCode::kFormat, "%s: maxval %d is not supported (only 255, 8-bit)",
             name.c_str(), maxval);
  const size_t need = static_cast<size_t>(img.width) * static_cast<size_t>(img.height) *
                      static_cast<size_t>(img.channels);
  const size_t offset = header.data_offset();
  const size_t have = bytes.size() >= offset ? bytes.size() - offset : 0;
  TLV_ENSURE(have == need, ErrorCode::kFormat,
             "%s: pixel data is %zu bytes, %dx%dx%d needs %zu (%s)", name.c_str(), have, img.width,
             img.height, img.channels, need,
             have < need ? "truncated" : "trailing bytes; multi-image files are not supported");
  // The pixel cap as for JPEG and PNG (the pixels are in the file, so the ratio holds at 1).
  TLV_TRY(image::check_decode_budget(img.width, img.height, img.channels, bytes.size(),
                                     /*max_ratio=*/1, "PPM/PGM", name.c_str()));
  img.pixels.resize(need);
  std::memcpy(img.pixels.data(), bytes.data() + offset, need);
  return img;
}

Result<Image> read_pnm(const std::string& path) {
  // A file over the pixel cap's RGB size plus a header cannot be a PNM the decoder accepts.
  const size_t limit = static_cast<size_t>(image::kMaxImagePixels) * 3 + 4096;
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, read_file(path, limit));
  return parse_pnm(bytes, path);
}

std::vector<std::byte> encode_pnm(const Image& image) {
  const std::string header = std::string(image.channels == 3 ? "P6\n" : "P5\n") +
                             std::to_string(image.width) + " " + std::to_string(image.height) +
                             "\n255\n";
  std::vector<std::byte> out(header.size() + image.pixels.size());
  std::memcpy(out.data(), header.data(), header.size());
  if (!image.pixels.empty())
    std::memcpy(out.data() + header.size(), image.pixels.data(), image.pixels.size());
  return out;
}

Status write_pnm(const std::string& path, const Image& image) {
  TLV_ENSURE(image.channels == 1 || image.channels == 3, ErrorCode::kInvalidArgument,
             "%s: cannot write a %d-channel image as PPM/PGM", path.c_str(), image.channels);
  return write_file(path, encode_pnm(image));
}

}  // namespace tlvlink::tools
