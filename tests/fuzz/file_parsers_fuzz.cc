// libFuzzer target for every byte parser besides the model loader and the stream protocol: the
// files a user points tlvlink at (model inputs, dataset members and indexes, recordings) and the
// frames a camera delivers. The first input byte picks the parser, the rest is its input:
//   0 .npy (parse_npy, then image_from_npy)        5 Touch100k data_list.json (the loader)
//   1 PNM  (parse_pnm)                             6 Touch-and-Go label file (the loader)
//   2 PNG  (decode_png)                            7 recorded raw stream (*.tlvraw, the reader)
//   3 JPEG (decode_jpeg at a scale from byte 1)    8 camera frame (FrameDecoder: the Mini's
//   4 TAG label line (parse_tag_label_line)          MJPEG with crop, DIGIT YUYV, NV12, GREY)
//                                                  9 MCAP file (read_mcap: tlvlink replay X.mcap)
// The loaders read a file, so modes 5-7 write the input into a private temporary directory
// first (slower, but it fuzzes the real line reader and its limits). Every result that parses
// is read in full. Run by tools/setup/run_tests.sh fuzz (seeds from make_parser_fuzz_corpus).

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/capture/recording.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "tlvlink/foxglove/mcap_reader.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/io/npy_image.h"
#include "tlvlink/io/png.h"
#include "tlvlink/io/pnm.h"

uint64_t g_parser_fuzz_sink = 0;

namespace {

using namespace tlvlink;

void read_pixels(const image::Image& img) {
  g_parser_fuzz_sink += static_cast<uint64_t>(img.width) * 3 + static_cast<uint64_t>(img.height);
  if (!img.pixels.empty()) g_parser_fuzz_sink += img.pixels.front() + img.pixels.back();
}

// A directory of our own for the whole run; inputs are written into it, never elsewhere.
const std::string& scratch_dir() {
  static const std::string dir = [] {
    char tmpl[] = "/tmp/tlvlink-parser-fuzz-XXXXXX";
    const char* d = mkdtemp(tmpl);
    if (d == nullptr) std::abort();
    return std::string(d);
  }();
  return dir;
}

void write_file(const std::string& path, std::span<const uint8_t> bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) std::abort();
  std::fclose(f);
}

void drain(datasets::TouchSampleLoader& loader) {
  datasets::TouchSample s;
  for (int i = 0; i < 1000; ++i) {  // the input is < 1 MB: far fewer lines than this
    auto r = loader.next(s);
    if (!r.ok() || !*r) break;
    g_parser_fuzz_sink += s.session.size() + loader.key().size() + s.sentence_desc.size();
  }
  g_parser_fuzz_sink += static_cast<uint64_t>(loader.report().problem_count());
}

void fuzz_npy(std::span<const std::byte> b) {
  auto a = tools::parse_npy(b, "fuzz.npy");
  if (!a.ok()) return;
  g_parser_fuzz_sink += a->shape.size() + a->data.size();
  if (auto img = tools::image_from_npy(*a, "fuzz.npy"); img.ok()) read_pixels(*img);
}

void fuzz_touch100k(std::span<const uint8_t> b) {
  const std::string dir = scratch_dir() + "/t100k";
  static const bool made = [&] {
    return system(("mkdir -p '" + dir + "/touch' '" + dir + "/vision'").c_str()) == 0;
  }();
  if (!made) std::abort();
  write_file(dir + "/data_list.json", b);
  datasets::Touch100kLoaderOptions o;
  o.load_images = false;
  if (auto l = datasets::open_touch100k(dir, o); l.ok()) drain(**l);
}

void fuzz_tag(std::span<const uint8_t> b) {
  const std::string dir = scratch_dir() + "/tag";
  static const bool made = [&] { return system(("mkdir -p '" + dir + "'").c_str()) == 0; }();
  if (!made) std::abort();
  write_file(dir + "/train.txt", b);
  write_file(dir + "/test.txt", b.subspan(b.size() / 2));
  datasets::TagLoaderOptions o;
  o.load_images = false;
  if (auto l = datasets::open_touch_and_go(dir, o); l.ok()) drain(**l);
}

void fuzz_recording(std::span<const uint8_t> b) {
  const std::string path = scratch_dir() + "/fuzz.tlvraw";
  write_file(path, b);
  auto r = capture::RecordingReader::open(path);
  if (!r.ok()) return;
  std::vector<uint8_t> frame;
  uint64_t offset = r->first_record();
  capture::RecordInfo info;
  for (int i = 0; i < 10000; ++i) {
    auto more = r->record_at(offset, info);
    if (!more.ok() || !*more) break;
    if (info.bytes > (size_t{1} << 22)) break;  // the input is < 1 MB; a record cannot be larger
    frame.resize(info.bytes);
    if (r->read_frame(info, frame, /*verify=*/true).ok() && !frame.empty())
      g_parser_fuzz_sink += frame.front();
    offset = info.next;
  }
}

void fuzz_camera_frame(uint8_t kind, std::span<const uint8_t> b) {
  // The formats the shipped sensor profiles stream, at their sizes (the decoders are made once).
  static std::vector<image::FrameDecoder> decoders = [] {
    std::vector<image::FrameDecoder> d;
    const auto add = [&](image::PixelFormat f, int32_t w, int32_t h, double crop,
                         image::Orientation o) {
      image::SensorView view{.width = 320, .height = 240, .crop = crop, .orientation = o};
      auto dec = image::FrameDecoder::create({.format = f, .width = w, .height = h}, view);
      if (!dec.ok()) std::abort();
      d.push_back(std::move(dec).value());
    };
    add(image::PixelFormat::kMjpeg, 3280, 2464, 0.15, image::Orientation::kUpright);  // Mini
    add(image::PixelFormat::kMjpeg, 320, 240, 0, image::Orientation::kUpright);       // R1.5
    add(image::PixelFormat::kYuyv, 320, 240, 0, image::Orientation::kUpright);
    add(image::PixelFormat::kNv12, 320, 240, 0, image::Orientation::kUpright);
    add(image::PixelFormat::kGrey, 320, 240, 0, image::Orientation::kUpright);
    return d;
  }();
  static std::vector<uint8_t> out(320 * 240 * 3);
  image::FrameDecoder& dec = decoders[kind % decoders.size()];
  if (dec.decode(b, out, "fuzz frame").ok()) g_parser_fuzz_sink += out[0] + out.back();
}

// A file that reads is read in full: every schema, channel and message.
void fuzz_mcap(std::span<const uint8_t> bytes) {
  auto f = foxglove::read_mcap(std::as_bytes(bytes), "fuzz.mcap");
  if (!f.ok()) return;
  for (const auto& s : f->schemas) g_parser_fuzz_sink += s.id + s.name.size() + s.data.size();
  for (const auto& c : f->channels) g_parser_fuzz_sink += c.id + c.topic.size() + c.metadata.size();
  for (const auto& m : f->messages) {
    g_parser_fuzz_sink += m.channel_id + m.log_time + m.data.size();
    if (!m.data.empty()) g_parser_fuzz_sink += static_cast<uint8_t>(m.data.back());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const uint8_t mode = data[0] % 10;
  const uint8_t arg = data[1];
  const std::span<const uint8_t> rest(data + 1, size - 1);
  const std::span<const std::byte> bytes = std::as_bytes(rest);
  switch (mode) {
    case 0: fuzz_npy(bytes); break;
    case 1:
      if (auto img = tools::parse_pnm(bytes, "fuzz.ppm"); img.ok()) read_pixels(*img);
      break;
    case 2:
      if (auto img = tools::decode_png(bytes, "fuzz.png"); img.ok()) read_pixels(*img);
      break;
    case 3: {
      static constexpr int32_t kScales[] = {1, 2, 4, 8};
      const std::span<const uint8_t> jpeg = rest.subspan(1);
      auto img = image::decode_jpeg(jpeg, "fuzz.jpg", kScales[arg % 4]);
      if (img.ok()) read_pixels(*img);
      break;
    }
    case 4: {
      const std::string_view line(reinterpret_cast<const char*>(rest.data()), rest.size());
      if (auto l = datasets::parse_tag_label_line(line); l.ok())
        g_parser_fuzz_sink += l->key.size() + static_cast<uint64_t>(l->label);
      break;
    }
    case 5: fuzz_touch100k(rest); break;
    case 6: fuzz_tag(rest); break;
    case 7: fuzz_recording(rest); break;
    case 8: fuzz_camera_frame(arg, rest.subspan(1)); break;
    case 9: fuzz_mcap(rest); break;
  }
  return 0;
}
