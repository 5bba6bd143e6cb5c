// Writes the seed corpus of file_parsers_fuzz: make_parser_fuzz_corpus DIR
// One or two valid inputs per mode (the mode byte first, as the fuzzer reads them), made by the
// project's own writers where it has one, so mutations start past each parser's first checks.

#include <png.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tlvlink/capture/recording.h"
#include "tlvlink/foxglove/mcap_writer.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/npy.h"

namespace {

using namespace tlvlink;
using Bytes = std::vector<uint8_t>;

int g_failures = 0;

void save(const std::string& dir, const std::string& name, uint8_t mode, const Bytes& body,
          int arg = -1) {
  Bytes b{mode};
  if (arg >= 0) b.push_back(static_cast<uint8_t>(arg));
  b.insert(b.end(), body.begin(), body.end());
  const std::string path = dir + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr || std::fwrite(b.data(), 1, b.size(), f) != b.size()) {
    std::fprintf(stderr, "make_parser_fuzz_corpus: cannot write %s\n", path.c_str());
    ++g_failures;
  }
  if (f != nullptr) std::fclose(f);
  std::printf("%-24s %7zu bytes\n", name.c_str(), b.size());
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

image::Image gradient(int32_t w, int32_t h) {
  image::Image img{.width = w, .height = h, .channels = 3, .pixels = {}};
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x)
      for (int32_t c = 0; c < 3; ++c)
        img.pixels.push_back(static_cast<uint8_t>(x * 7 + y * 3 + c * 50));
  return img;
}

Bytes png_of(const image::Image& img) {
  png_image p{};
  p.version = PNG_IMAGE_VERSION;
  p.width = static_cast<png_uint_32>(img.width);
  p.height = static_cast<png_uint_32>(img.height);
  p.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&p, nullptr, &size, 0, img.pixels.data(), 0, nullptr)) return {};
  Bytes out(size);
  if (!png_image_write_to_memory(&p, out.data(), &size, 0, img.pixels.data(), 0, nullptr))
    return {};
  out.resize(size);
  return out;
}

Bytes recording(const std::string& dir, const Bytes& frame) {
  const std::string path = dir + "/.seed.tlvraw";
  capture::RecordingFormat f;
  f.format = {.format = image::PixelFormat::kYuyv, .width = 8, .height = 4, .stride = 0};
  f.fps_numerator = 60;
  auto w = capture::RecordingWriter::create(path, f);
  if (!w.ok()) return {};
  auto first = w->append(frame, 1'000'000, 0);
  if (!first.ok() || !w->append(frame, 17'000'000, 1, capture::kRecordErrorFlag).ok() ||
      !w->append_repeat(*first, 34'000'000, 3).ok() || !w->close().ok())
    return {};
  std::ifstream in(path, std::ios::binary);
  Bytes out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  unlink(path.c_str());
  return out;
}

// An MCAP file as tlvlink writes one: two schemas, a channel with metadata, one without schema,
// messages in several chunks (small chunks: more structure for the mutator to hit).
Bytes mcap(const std::string& dir) {
  const std::string path = dir + "/.seed.mcap";
  foxglove::McapWriterOptions o;
  o.chunk_bytes = 96;
  auto w = foxglove::McapWriter::create(path, true, o);
  if (!w.ok()) return {};
  auto& m = *w.value();
  const std::string payload = "{\"type\":\"frame_prediction\",\"contact\":true}";
  const auto data = std::as_bytes(std::span(payload.data(), payload.size()));
  if (!m.add_schema({1, "tlvlink.FramePrediction", "jsonschema", "{\"type\":\"object\"}"}).ok() ||
      !m.add_schema({2, "tlvlink.Stats", "jsonschema", "{}"}).ok() ||
      !m.add_channel({1, 1, "/tlvlink/frame_prediction", "json", {{"k", "v"}}}).ok() ||
      !m.add_channel({2, 2, "/tlvlink/stats", "json", {}}).ok() ||
      !m.add_channel({100, 0, "/tlvlink/records", "tlvlink.record", {}}).ok())
    return {};
  for (uint64_t i = 0; i < 6; ++i) {
    if (!m.write_message(static_cast<uint16_t>(i % 3 == 2 ? 100 : i % 2 + 1), 1000 * i,
                         1000 * i + 5, data)
             .ok())
      return {};
  }
  if (!m.close().ok()) return {};
  std::ifstream in(path, std::ios::binary);
  Bytes out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  unlink(path.c_str());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_parser_fuzz_corpus DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  const image::Image small = gradient(12, 8);

  std::vector<uint8_t> px = small.pixels;
  auto npy = tools::encode_npy(tools::NpyArray::from<uint8_t>({8, 12, 3}, px));
  std::vector<float> fl(2 * 3 * 4);
  for (size_t i = 0; i < fl.size(); ++i) fl[i] = 0.25f * static_cast<float>(i);
  auto npy_f = tools::encode_npy(tools::NpyArray::from<float>({2, 3, 4}, fl), 2);
  if (!npy.ok() || !npy_f.ok()) return 1;
  const auto as_u8 = [](const std::vector<std::byte>& b) {
    return Bytes(reinterpret_cast<const uint8_t*>(b.data()),
                 reinterpret_cast<const uint8_t*>(b.data()) + b.size());
  };
  save(dir, "npy_u8", 0, as_u8(*npy));
  save(dir, "npy_f32_v2", 0, as_u8(*npy_f));

  Bytes ppm = text("P6\n# seed\n12 8\n255\n");
  ppm.insert(ppm.end(), small.pixels.begin(), small.pixels.end());
  save(dir, "ppm", 1, ppm);
  Bytes pgm = text("P5 4 2 255\n");
  for (int i = 0; i < 8; ++i) pgm.push_back(static_cast<uint8_t>(i * 30));
  save(dir, "pgm", 1, pgm);

  save(dir, "png", 2, png_of(small));

  auto jpeg = image::encode_jpeg(small, 80);
  auto jpeg_cam = image::encode_jpeg(gradient(320, 240), 60);
  if (!jpeg.ok() || !jpeg_cam.ok()) return 1;
  save(dir, "jpeg_s1", 3, *jpeg, 0);
  save(dir, "jpeg_s8", 3, *jpeg, 3);
  // Issue 12's decompression bomb: 136 bytes declaring 16384x16384 (~800 MB before the decode
  // budget). Under the fuzz memory limits it must stay an error, never an allocation.
  Bytes bomb = {0xFF, 0xD8, 0xFF, 0xDB, 0x00, 0x43, 0x00};
  bomb.insert(bomb.end(), 64, 1);
  bomb.insert(bomb.end(), {0xFF, 0xC0, 0x00, 0x0B, 0x08, 0x40, 0x00, 0x40, 0x00, 0x01, 0x01, 0x11,
                           0x00, 0xFF, 0xDA, 0x00, 0x08, 0x01, 0x01, 0x00, 0x00, 0x3F, 0x00});
  bomb.insert(bomb.end(), 40, 0);
  bomb.insert(bomb.end(), {0xFF, 0xD9});
  save(dir, "jpeg_bomb_16k", 3, bomb, 0);

  save(dir, "tag_line", 4, text("20220917_000526/0000000012.jpg,3\r"));

  save(dir, "touch100k_index", 5,
       text("{\"img\": \"20220917_000526/0000000012.jpg\", \"sentence_desc\": \"a smooth hard "
            "surface\", \"phrase_desc\": \"smooth, hard\"}\n"
            "{\"img\": \"s2/0000000001.png\", \"sentence_desc\": \"soft\", \"phrase_desc\": "
            "[\"soft\", \" rough \"]}\n\n"));
  save(dir, "tag_labels", 6,
       text("20220917_000526/0000000012.jpg,3\n20220917_000526/0000000013.jpg,17\n"
            "20220918_101010/0000000001.jpg,0\n"));

  Bytes yuyv_small(8 * 4 * 2);
  for (size_t i = 0; i < yuyv_small.size(); ++i) yuyv_small[i] = static_cast<uint8_t>(i * 5);
  save(dir, "recording", 7, recording(dir, yuyv_small));

  // Camera frames: 0 the Mini's MJPEG decoder (a small JPEG: the wrong size, still a path),
  // 1 320x240 MJPEG, 2 YUYV, 3 NV12, 4 GREY (file_parsers_fuzz's decoder order).
  save(dir, "frame_mjpeg_mini", 8, *jpeg_cam, 0);
  save(dir, "frame_mjpeg", 8, *jpeg_cam, 1);
  Bytes yuyv(320 * 240 * 2), nv12(320 * 240 * 3 / 2), grey(320 * 240);
  for (size_t i = 0; i < yuyv.size(); ++i) yuyv[i] = static_cast<uint8_t>(i % 251);
  for (size_t i = 0; i < nv12.size(); ++i) nv12[i] = static_cast<uint8_t>(i % 241);
  for (size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<uint8_t>(i % 239);
  save(dir, "frame_yuyv", 8, yuyv, 2);
  save(dir, "frame_nv12", 8, nv12, 3);
  save(dir, "frame_grey", 8, grey, 4);
  const Bytes mcap_seed = mcap(dir);
  if (mcap_seed.empty())
    ++g_failures, std::fprintf(stderr, "make_parser_fuzz_corpus: cannot write the MCAP seed\n");
  save(dir, "mcap", 9, mcap_seed);
  return g_failures == 0 ? 0 : 1;
}
