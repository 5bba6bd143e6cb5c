#include "tlvlink/record/record.h"

#include <sys/stat.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "tlvlink/capture/recording.h"
#include "tlvlink/datasets/feel.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/png.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::record {
namespace {

namespace fs = std::filesystem;

constexpr size_t kMaxImageFileBytes = 64u << 20;  // one camera frame; larger is not a frame

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// One frame to append: JPEG bytes (kept) or an RGB image (encoded).
struct Frame {
  std::vector<uint8_t> jpeg;
  image::Image rgb;
  std::string name;
};

// Yields the input's frames one at a time; false at the end.
using FrameReader = std::function<Result<bool>(Frame&)>;

Result<FrameReader> images_in(const std::string& dir, bool& as_is,
                              std::vector<std::string>& skipped) {
  std::error_code ec;
  TLV_ENSURE(fs::is_directory(dir, ec), ErrorCode::kIo, "record: %s is not a directory",
             dir.c_str());
  auto files = std::make_shared<std::vector<fs::path>>();
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string ext = lower_extension(e.path());
    const bool image =
        ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".ppm" || ext == ".pnm";
    struct stat st {};
    const bool stat_ok = ::stat(e.path().c_str(), &st) == 0;  // never opens: a FIFO cannot block it
    if (stat_ok && S_ISREG(st.st_mode)) {
      if (image) files->push_back(e.path());
    } else if (image || (stat_ok && S_ISDIR(st.st_mode))) {
      // A FIFO or device named like a frame, or a subfolder (not descended into): named.
      skipped.push_back(
          e.path().string() + ": " +
          (stat_ok ? std::string("not a regular file (") + file_type_name(st.st_mode) + ")"
                   : std::string("cannot stat")));
    }
  }
  std::sort(skipped.begin(), skipped.end());
  TLV_ENSURE(!ec, ErrorCode::kIo, "record: cannot list %s: %s", dir.c_str(), ec.message().c_str());
  TLV_ENSURE(!files->empty(), ErrorCode::kInvalidArgument,
             "record: %s holds no .jpg, .jpeg, .png, .ppm or .pnm file", dir.c_str());
  std::sort(files->begin(), files->end());
  as_is = std::all_of(files->begin(), files->end(), [](const fs::path& p) {
    const std::string e = lower_extension(p);
    return e == ".jpg" || e == ".jpeg";
  });
  auto next = std::make_shared<size_t>(0);
  return FrameReader([files, next, as_is](Frame& f) -> Result<bool> {
    if (*next >= files->size()) return false;
    const fs::path p = (*files)[(*next)++];
    f.name = p.string();
    const std::string ext = lower_extension(p);
    if (ext == ".jpg" || ext == ".jpeg") {
      TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes,
                           tools::read_file(f.name, kMaxImageFileBytes));
      f.jpeg.assign(reinterpret_cast<const uint8_t*>(bytes.data()),
                    reinterpret_cast<const uint8_t*>(bytes.data()) + bytes.size());
      if (!as_is) {
        TLV_ASSIGN_OR_RETURN(f.rgb, image::decode_jpeg(f.jpeg, f.name));
        f.jpeg.clear();
      }
    } else if (ext == ".png") {
      TLV_ASSIGN_OR_RETURN(f.rgb, tools::read_png(f.name));
    } else {
      TLV_ASSIGN_OR_RETURN(f.rgb, tools::read_pnm(f.name));
    }
    return true;
  });
}

image::Image image_of(const datasets::RgbImage& in) {
  image::Image out;
  out.width = in.width;
  out.height = in.height;
  out.channels = 3;
  out.pixels = in.rgb;
  return out;
}

Result<FrameReader> touch_frames(std::unique_ptr<datasets::TouchSampleLoader> loader) {
  auto l = std::shared_ptr<datasets::TouchSampleLoader>(std::move(loader));
  auto sample = std::make_shared<datasets::TouchSample>();
  return FrameReader([l, sample](Frame& f) -> Result<bool> {
    TLV_ASSIGN_OR_RETURN(const bool more, l->next(*sample));
    if (!more) return false;
    f.name = l->key();
    f.rgb = image_of(sample->touch);
    return true;
  });
}

Result<FrameReader> feel_frames(std::unique_ptr<datasets::GraspEpisodeLoader> loader,
                                int32_t finger) {
  auto l = std::shared_ptr<datasets::GraspEpisodeLoader>(std::move(loader));
  auto episode = std::make_shared<datasets::GraspEpisode>();
  auto moment = std::make_shared<int32_t>(datasets::kMoments);
  return FrameReader([l, episode, moment, finger](Frame& f) -> Result<bool> {
    if (*moment == datasets::kMoments) {
      TLV_ASSIGN_OR_RETURN(const bool more, l->next(*episode));
      if (!more) return false;
      *moment = 0;
    }
    f.name = l->key() + " " + heads::moment_name(static_cast<heads::Moment>(*moment));
    f.rgb = image_of(episode->frames[finger][*moment]);
    ++*moment;
    return true;
  });
}

// A dataset item that does not load is skipped by the loader; the report names it.
template <typename Loader>
void name_problems(Loader& l, std::vector<std::string>& skipped) {
  l.report().on_problem = [&skipped](const datasets::LoadProblem& p) {
    skipped.push_back(p.to_string());
  };
}

Result<FrameReader> open_input(const RecordOptions& o, bool& as_is,
                               std::vector<std::string>& skipped) {
  as_is = false;
  switch (o.source) {
    case RecordSource::kImages: return images_in(o.input, as_is, skipped);
    case RecordSource::kTouch100k: {
      datasets::Touch100kLoaderOptions lo;
      lo.load_vision = false;
      lo.require_vision = false;
      TLV_ASSIGN_OR_RETURN(auto l, datasets::open_touch100k(o.input, lo));
      name_problems(*l, skipped);
      return touch_frames(std::move(l));
    }
    case RecordSource::kTouchAndGo: {
      datasets::TagLoaderOptions lo;
      lo.load_vision = false;
      lo.require_vision = false;
      TLV_ASSIGN_OR_RETURN(auto l, datasets::open_touch_and_go(o.input, lo));
      name_problems(*l, skipped);
      return touch_frames(std::move(l));
    }
    case RecordSource::kFeel: {
      datasets::FeelLoaderOptions lo;
      lo.load_vision = false;
      lo.require_vision = false;
      // The Feel HDF5 files (a file, or a folder holding *.h5), else TLV-Link's repacked layout.
      std::error_code ec;
      bool h5 = !fs::is_directory(o.input, ec);
      if (!h5) {
        for (const auto& e : fs::directory_iterator(o.input, ec))
          h5 = h5 || lower_extension(e.path()) == ".h5";
      }
      const bool repacked = !h5;
      auto l =
          repacked ? datasets::open_feel_repacked(o.input, lo) : datasets::open_feel(o.input, lo);
      if (!l.ok()) return l.error();
      name_problems(**l, skipped);
      return feel_frames(std::move(l).value(), o.finger);
    }
  }
  return Error::make(ErrorCode::kInvalidArgument, "record: unknown source");
}

Status check_options(const RecordOptions& o, const std::string& out_path);
// Fills `report` in place: a dataset loader reports the items it skips into report.skipped while
// it is read, through a reference taken by open_input.
Status write_recording(const FrameReader& read, const RecordOptions& o, const std::string& out_path,
                       RecordReport& report);

}  // namespace

Result<RecordReport> record_frames(const RecordOptions& o, const std::string& out_path) {
  TLV_TRY(check_options(o, out_path));
  RecordReport report;
  TLV_ASSIGN_OR_RETURN(FrameReader read, open_input(o, report.stored_as_is, report.skipped));
  TLV_TRY(write_recording(read, o, out_path, report));
  return report;
}

Result<RecordReport> record_jpeg_frames(JpegFrameSource frames, const RecordOptions& o,
                                        const std::string& out_path) {
  TLV_TRY(check_options(o, out_path));
  RecordReport report;
  report.stored_as_is = true;
  const FrameReader read = [&frames](Frame& f) -> Result<bool> {
    f.rgb = {};
    return frames(f.jpeg, f.name);
  };
  TLV_TRY(write_recording(read, o, out_path, report));
  return report;
}

namespace {

Status check_options(const RecordOptions& o, const std::string& out_path) {
  TLV_ENSURE(o.fps > 0 && o.fps <= 1000, ErrorCode::kInvalidArgument,
             "record: fps = %g is outside (0, 1000]", o.fps);
  TLV_ENSURE(o.hold >= 1 && o.hold <= 10000, ErrorCode::kInvalidArgument,
             "record: hold = %d is outside 1..10000", o.hold);
  TLV_ENSURE(o.limit >= 0 && o.finger >= 0 && o.finger <= 1 && o.jpeg_quality >= 1 &&
                 o.jpeg_quality <= 100,
             ErrorCode::kInvalidArgument, "record: limit %lld, finger %d, jpeg quality %d",
             static_cast<long long>(o.limit), o.finger, o.jpeg_quality);
  std::error_code ec;
  TLV_ENSURE(o.overwrite || !fs::exists(out_path, ec), ErrorCode::kInvalidArgument,
             "record: %s exists (--overwrite replaces it)", out_path.c_str());
  return {};
}

Status write_recording(const FrameReader& read, const RecordOptions& o, const std::string& out_path,
                       RecordReport& report) {
  const std::string temp = out_path + ".partial";
  std::optional<capture::RecordingWriter> writer;
  image::JpegDecoder header_reader;
  const int64_t period = std::llround(1e9 / o.fps);
  Frame f;
  int64_t t = 0;
  uint32_t seq = 0;
  const auto fail = [&](const Error& e) {
    writer.reset();
    std::remove(temp.c_str());
    return e;
  };
  for (;;) {
    if (o.limit > 0 && report.images >= o.limit) break;
    auto more = read(f);
    if (!more.ok()) return fail(more.error());
    if (!*more) break;
    std::vector<uint8_t> encoded;
    int32_t w = f.rgb.width, h = f.rgb.height;
    if (!f.jpeg.empty()) {
      auto hdr = header_reader.read_header(f.jpeg, f.name.c_str());
      if (!hdr.ok()) return fail(hdr.error());
      w = hdr->width;
      h = hdr->height;
    } else {
      auto e = image::encode_jpeg(f.rgb, o.jpeg_quality);
      if (!e.ok()) return fail(e.error().with_context("%s", f.name.c_str()));
      encoded = std::move(e).value();
    }
    const std::vector<uint8_t>& bytes = f.jpeg.empty() ? encoded : f.jpeg;
    if (!writer) {
      capture::RecordingFormat format;
      format.format = {image::PixelFormat::kMjpeg, w, h, 0};
      format.fps_numerator = static_cast<uint32_t>(std::lround(o.fps * 1000));
      format.fps_denominator = 1000;
      capture::WriterOptions wo;
      wo.origin_ns = 0;
      wo.overwrite = true;
      auto created = capture::RecordingWriter::create(temp, format, wo);
      if (!created.ok()) return fail(created.error());
      writer.emplace(std::move(created).value());
      report.width = w;
      report.height = h;
    } else if (w != report.width || h != report.height) {
      return fail(Error::make(ErrorCode::kShapeMismatch,
                              "record: %s is %dx%d, the stream's frames are %dx%d (a camera "
                              "streams one size; resize the inputs first)",
                              f.name.c_str(), w, h, report.width, report.height));
    }
    auto first = writer->append(bytes, t, seq++);
    if (!first.ok()) return fail(first.error());
    t += period;
    for (int32_t k = 1; k < o.hold; ++k, t += period) {
      if (Status st = writer->append_repeat(*first, t, seq++); !st.ok()) return fail(st.error());
    }
    ++report.images;
  }
  TLV_ENSURE(writer.has_value(), ErrorCode::kInvalidArgument, "record: %s gave no frame",
             o.input.c_str());
  report.frames = static_cast<int64_t>(writer->frames());
  report.file_bytes = static_cast<int64_t>(writer->file_bytes());
  if (Status st = writer->close(); !st.ok()) return fail(st.error());
  TLV_ENSURE(std::rename(temp.c_str(), out_path.c_str()) == 0, ErrorCode::kIo,
             "record: cannot rename %s to %s", temp.c_str(), out_path.c_str());
  return {};
}

}  // namespace
}  // namespace tlvlink::record
