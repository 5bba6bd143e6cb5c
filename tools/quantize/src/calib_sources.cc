// Calibration sources: the dataset loaders (Touch100k, Touch-and-Go, Feel HDF5 / repacked) and
// image folders, listed without images first, then read for the selected items only.

#include "calib_sources.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>

#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/feel.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/png.h"
#include "tlvlink/io/pnm.h"

namespace tlvlink::quantize::calib_sources {
namespace {

namespace fs = std::filesystem;

tools::Image to_image(const datasets::RgbImage& rgb) {
  return tools::Image{rgb.width, rgb.height, 3, rgb.rgb};
}

Result<std::unique_ptr<datasets::TouchSampleLoader>> open_touch(
    CalibFormat format, const std::string& path, bool images,
    datasets::Split split = datasets::Split::kAll) {
  datasets::LoaderOptions base;
  base.load_images = images;
  base.load_vision = false;
  base.require_vision = false;
  if (format == CalibFormat::kTouch100k) {
    datasets::Touch100kLoaderOptions o;
    static_cast<datasets::LoaderOptions&>(o) = base;
    // Labels are not needed for calibration; the listing pass (no images) reads the sidecar for
    // the split it records.
    o.use_sidecar = !images;
    return datasets::open_touch100k(path, o);
  }
  datasets::TagLoaderOptions o;
  static_cast<datasets::LoaderOptions&>(o) = base;
  o.split = split;
  o.use_sidecar = false;
  return datasets::open_touch_and_go(path, o);
}

Result<std::unique_ptr<datasets::GraspEpisodeLoader>> open_grasp(
    CalibFormat format, const std::string& path, bool images,
    datasets::Split split = datasets::Split::kAll) {
  datasets::FeelLoaderOptions o;
  o.load_images = images;
  o.load_vision = false;
  o.require_vision = false;
  o.split = split;
  return format == CalibFormat::kFeel ? datasets::open_feel(path, o)
                                      : datasets::open_feel_repacked(path, o);
}

Result<std::vector<std::string>> image_files(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  fs::recursive_directory_iterator it(dir, ec), end;
  TLV_ENSURE(!ec, ErrorCode::kIo, "cannot read directory '%s': %s", dir.c_str(),
             ec.message().c_str());
  for (; it != end; it.increment(ec)) {
    TLV_ENSURE(!ec, ErrorCode::kIo, "reading '%s': %s", dir.c_str(), ec.message().c_str());
    // A FIFO or a device named like an image is listed too: reading it fails at once
    // (RegularFile) and the failure names it, instead of it being left out unseen.
    std::error_code kind;
    if (is_image_file(it->path().string()) && !it->is_directory(kind))
      files.push_back(fs::relative(it->path(), dir).generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool ends_with(std::string s, const char* suffix) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  const std::string x(suffix);
  return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

}  // namespace

bool is_image_file(const std::string& path) {
  for (const char* ext : {".jpg", ".jpeg", ".ppm", ".pgm", ".pnm", ".png"})
    if (ends_with(path, ext)) return true;
  return false;
}

Result<tools::Image> read_image(const std::string& path) {
  if (ends_with(path, ".jpg") || ends_with(path, ".jpeg")) return tools::read_jpeg(path);
  if (ends_with(path, ".png")) return tools::read_png(path);
  return tools::read_pnm(path);
}

namespace {

Result<std::vector<Item>> list_all(CalibFormat format, const std::string& path,
                                   datasets::Split split, datasets::ProblemEcho* problems) {
  std::vector<Item> items;
  switch (format) {
    case CalibFormat::kTouch100k:
    case CalibFormat::kTag: {
      TLV_ASSIGN_OR_RETURN(auto loader, open_touch(format, path, false, split));
      if (problems != nullptr) loader->report().on_problem = problems->callback();
      datasets::TouchSample s;
      for (;;) {
        TLV_ASSIGN_OR_RETURN(const bool more, loader->next(s));
        if (!more) break;
        items.push_back({loader->key(), s.session.empty() ? loader->key() : s.session, 0,
                         loader->recorded_split()});
      }
      return items;
    }
    case CalibFormat::kFeel:
    case CalibFormat::kFeelRepacked: {
      TLV_ASSIGN_OR_RETURN(auto loader, open_grasp(format, path, false, split));
      if (problems != nullptr) loader->report().on_problem = problems->callback();
      datasets::GraspEpisode e;
      for (;;) {
        TLV_ASSIGN_OR_RETURN(const bool more, loader->next(e));
        if (!more) break;
        for (int32_t f = 0; f < heads::kFingers * heads::kMoments; ++f)
          items.push_back(
              {loader->key(), e.object_name.empty() ? loader->key() : e.object_name, f});
      }
      return items;
    }
    case CalibFormat::kImages: {
      TLV_ASSIGN_OR_RETURN(std::vector<std::string> files, image_files(path));
      for (const std::string& f : files) {
        const std::string parent = fs::path(f).parent_path().generic_string();
        items.push_back({f, parent.empty() ? f : parent, 0});
      }
      return items;
    }
    case CalibFormat::kAuto:
    case CalibFormat::kExtreme: break;
  }
  return Error::make(ErrorCode::kInvalidArgument, "format %s has no item list",
                     calib_format_name(format));
}

}  // namespace

namespace {

datasets::DatasetFormat dataset_format_of(CalibFormat format) {
  switch (format) {
    case CalibFormat::kTag: return datasets::DatasetFormat::kTouchAndGo;
    case CalibFormat::kFeel: return datasets::DatasetFormat::kFeelHdf5;
    case CalibFormat::kFeelRepacked: return datasets::DatasetFormat::kFeelRepacked;
    default: return datasets::DatasetFormat::kTouch100k;
  }
}

}  // namespace

Result<std::vector<Item>> list_items(CalibFormat format, const std::string& path,
                                     datasets::Split split, datasets::ProblemEcho* problems) {
  const bool dataset = format != CalibFormat::kImages;
  const std::optional<datasets::HashSplit> hash =
      dataset ? datasets::split_to_apply(path, dataset_format_of(format), std::nullopt)
              : std::optional<datasets::HashSplit>(datasets::kDefaultSplit);
  // TAG and Feel loaders read the split they record themselves; Touch100k's is per item (the
  // sidecar), checked below.
  const bool recorded_in_loader = !hash && format != CalibFormat::kTouch100k;
  TLV_ASSIGN_OR_RETURN(
      std::vector<Item> items,
      list_all(format, path, recorded_in_loader ? split : datasets::Split::kAll, problems));
  if (split == datasets::Split::kAll || recorded_in_loader) return items;
  std::vector<Item> kept;
  for (Item& item : items) {
    bool test = false;
    if (!hash) {
      TLV_ENSURE(item.recorded != datasets::Split::kAll, ErrorCode::kFormat,
                 "%s: '%s' has no recorded split in %s", path.c_str(), item.key.c_str(),
                 datasets::kTouch100kSidecar);
      test = item.recorded == datasets::Split::kTest;
    } else {
      test = datasets::hash_split_is_test(item.group, *hash);
    }
    if (datasets::split_selects(split, test)) kept.push_back(std::move(item));
  }
  return kept;
}

Status read_frames(CalibFormat format, const std::string& path,
                   const std::unordered_set<std::string>& wanted, const FrameVisitor& visit,
                   std::string& load_summary, const std::function<void()>& on_item,
                   const std::function<void(const std::string&)>& on_note,
                   datasets::ProblemEcho* problems) {
  size_t seen = 0;
  switch (format) {
    case CalibFormat::kTouch100k:
    case CalibFormat::kTag: {
      TLV_ASSIGN_OR_RETURN(auto loader, open_touch(format, path, true));
      // Index lines were reported by the listing pass.
      if (problems != nullptr) loader->report().on_problem = problems->callback(false);
      datasets::TouchSample s;
      while (seen < wanted.size()) {
        TLV_ASSIGN_OR_RETURN(const bool more, loader->next(s));
        if (!more) break;
        const Item item{loader->key(), s.session, 0};
        if (wanted.count(item.id()) == 0) continue;
        ++seen;
        if (on_item) on_item();
        TLV_TRY(visit(item, to_image(s.touch)));
      }
      load_summary = loader->report().summary();
      return {};
    }
    case CalibFormat::kFeel:
    case CalibFormat::kFeelRepacked: {
      TLV_ASSIGN_OR_RETURN(auto loader, open_grasp(format, path, true));
      // Index lines were reported by the listing pass.
      if (problems != nullptr) loader->report().on_problem = problems->callback(false);
      datasets::GraspEpisode e;
      while (seen < wanted.size()) {
        TLV_ASSIGN_OR_RETURN(const bool more, loader->next(e));
        if (!more) break;
        for (int32_t f = 0; f < heads::kFingers * heads::kMoments; ++f) {
          const Item item{loader->key(), e.object_name, f};
          if (wanted.count(item.id()) == 0) continue;
          ++seen;
          if (on_item) on_item();
          TLV_TRY(visit(item, to_image(e.frames[f / heads::kMoments][f % heads::kMoments])));
        }
      }
      load_summary = loader->report().summary();
      return {};
    }
    case CalibFormat::kImages: {
      TLV_ASSIGN_OR_RETURN(std::vector<std::string> files, image_files(path));
      int64_t loaded = 0, failed = 0;
      for (const std::string& f : files) {
        if (seen == wanted.size()) break;
        const Item item{f, "", 0};
        if (wanted.count(item.id()) == 0) continue;
        ++seen;
        if (on_item) on_item();
        auto image = read_image((fs::path(path) / f).string());
        if (!image.ok()) {  // counted and skipped, like the dataset loaders do
          if (on_note) on_note(std::string("skipping ") + image.error().message());
          ++failed;
          continue;
        }
        ++loaded;
        TLV_TRY(visit(item, *image));
      }
      load_summary = std::to_string(loaded) + " images loaded" +
                     (failed > 0 ? "; " + std::to_string(failed) + " unreadable (skipped)" : "");
      return {};
    }
    case CalibFormat::kAuto:
    case CalibFormat::kExtreme: break;
  }
  return Error::make(ErrorCode::kInvalidArgument, "format %s cannot be read here",
                     calib_format_name(format));
}

}  // namespace tlvlink::quantize::calib_sources
