// Calibration / held-out frame selection and loading (calib_data.h).

#include "tlvlink/quantize/calib_data.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <unordered_set>

#include "calib_sources.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/npy_image.h"
#include "tlvlink/io/progress.h"
#include "tlvlink/sim/extreme.h"

namespace tlvlink::quantize {
namespace {

namespace fs = std::filesystem;
using calib_sources::Item;

// Extreme-set held-out frames use seeds this far from the calibration ones.
constexpr uint64_t kHeldoutSeedOffset = 1000003;
// Salt so the item ranking is independent of the group ranking.
constexpr uint64_t kItemSalt = 0x9e3779b97f4a7c15ull;

struct Selection {
  std::unordered_set<std::string> calibration, heldout;
  size_t groups = 0, heldout_groups = 0;
  bool shared_group = false;  // a single group: held-out frames come from it too
};

std::vector<size_t> take_ranked(const std::vector<Item>& items, const std::vector<size_t>& pool,
                                int64_t count, uint64_t seed) {
  std::vector<std::pair<double, size_t>> ranked;
  for (size_t i : pool)
    ranked.emplace_back(datasets::split_hash_unit(items[i].id(), seed ^ kItemSalt), i);
  std::sort(ranked.begin(), ranked.end());
  std::vector<size_t> out;
  for (size_t k = 0; k < ranked.size() && static_cast<int64_t>(out.size()) < count; ++k)
    out.push_back(ranked[k].second);
  return out;
}

Selection select(const std::vector<Item>& items, const CalibDataOptions& o) {
  std::map<std::string, std::vector<size_t>> by_group;
  for (size_t i = 0; i < items.size(); ++i) by_group[items[i].group].push_back(i);
  std::vector<std::pair<double, const std::string*>> groups;
  for (const auto& [g, _] : by_group) groups.emplace_back(datasets::split_hash_unit(g, o.seed), &g);
  std::sort(groups.begin(), groups.end());
  Selection s;
  s.groups = groups.size();
  std::vector<size_t> calib_pool, heldout_pool;
  if (o.heldout_count > 0 && groups.size() == 1) {
    // One group: split its items (the summary says held-out frames share it).
    std::vector<size_t> all(items.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    const int64_t h = std::min<int64_t>(o.heldout_count, static_cast<int64_t>(items.size() / 2));
    heldout_pool = take_ranked(items, all, h, o.seed + 1);
    const std::unordered_set<size_t> held(heldout_pool.begin(), heldout_pool.end());
    for (size_t i : all)
      if (held.count(i) == 0) calib_pool.push_back(i);
    s.shared_group = true;
  } else {
    for (const auto& [rank, g] : groups) {
      const std::vector<size_t>& members = by_group[*g];
      const bool to_heldout = static_cast<int64_t>(heldout_pool.size()) < o.heldout_count &&
                              s.heldout_groups + 1 < groups.size();
      std::vector<size_t>& pool = to_heldout ? heldout_pool : calib_pool;
      pool.insert(pool.end(), members.begin(), members.end());
      s.heldout_groups += to_heldout ? 1 : 0;
    }
  }
  for (size_t i : take_ranked(items, calib_pool, o.calib_count, o.seed))
    s.calibration.insert(items[i].id());
  for (size_t i : take_ranked(items, heldout_pool, o.heldout_count, o.seed))
    s.heldout.insert(items[i].id());
  return s;
}

Status render_extreme(const CalibDataOptions& o, const InputSpec& spec, CalibData& out) {
  const std::span<const sim::ExtremeCase> cases = sim::extreme_cases();
  TLV_ENSURE(!cases.empty(), ErrorCode::kInvalidArgument, "the extreme set is empty");
  const auto n = static_cast<int64_t>(cases.size());
  auto render = [&](int64_t count, uint64_t base, std::vector<std::vector<float>>& frames,
                    std::vector<std::string>& keys) -> Status {
    for (int64_t i = 0; i < count; ++i) {
      const sim::ExtremeCase& c = cases[static_cast<size_t>(i % n)];
      const uint64_t seed = base + static_cast<uint64_t>(i / n);
      const std::string key = std::string(c.name) + "@" + std::to_string(seed);
      auto renderer = sim::Renderer::create(c.sensor, seed);
      if (!renderer.ok()) return renderer.error().with_context("extreme %s", key.c_str());
      sim::Frame frame;
      if (Status s = (*renderer)->render(c.scene, c.options, seed, frame); !s.ok())
        return s.error().with_context("extreme %s", key.c_str());
      auto x = image::preprocess(tools::Image{frame.width, frame.height, 3, frame.rgb}, spec);
      if (!x.ok()) return x.error().with_context("preprocessing extreme %s", key.c_str());
      frames.push_back(std::move(x).value());
      keys.push_back(key);
    }
    return {};
  };
  TLV_TRY(render(o.calib_count, o.seed, out.calibration, out.calibration_keys));
  TLV_TRY(render(o.heldout_count, o.seed + kHeldoutSeedOffset, out.heldout, out.heldout_keys));
  out.summary = "extreme set: " + std::to_string(n) + " named scenes; calibration " +
                std::to_string(out.calibration.size()) + " frames (seeds from " +
                std::to_string(o.seed) + "), held-out " + std::to_string(out.heldout.size()) +
                " frames of the same scenes on another sensor instance and noise (seeds from " +
                std::to_string(o.seed + kHeldoutSeedOffset) + ")";
  return {};
}

}  // namespace

const char* calib_format_name(CalibFormat format) {
  switch (format) {
    case CalibFormat::kAuto: return "auto";
    case CalibFormat::kTouch100k: return "touch100k";
    case CalibFormat::kTag: return "tag";
    case CalibFormat::kFeel: return "feel";
    case CalibFormat::kFeelRepacked: return "feel-repacked";
    case CalibFormat::kImages: return "images";
    case CalibFormat::kExtreme: return "extreme";
  }
  return "?";
}

Result<CalibFormat> parse_calib_format(const std::string& name) {
  for (CalibFormat f :
       {CalibFormat::kAuto, CalibFormat::kTouch100k, CalibFormat::kTag, CalibFormat::kFeel,
        CalibFormat::kFeelRepacked, CalibFormat::kImages, CalibFormat::kExtreme}) {
    if (name == calib_format_name(f)) return f;
  }
  return Error::make(ErrorCode::kInvalidArgument, "unknown calibration format '%s'", name.c_str());
}

CalibFormat calib_format_of(datasets::DatasetFormat format) {
  switch (format) {
    case datasets::DatasetFormat::kTouch100k: return CalibFormat::kTouch100k;
    case datasets::DatasetFormat::kTouchAndGo: return CalibFormat::kTag;
    case datasets::DatasetFormat::kFeelHdf5: return CalibFormat::kFeel;
    case datasets::DatasetFormat::kFeelRepacked: return CalibFormat::kFeelRepacked;
  }
  return CalibFormat::kAuto;
}

Result<CalibFormat> detect_calib_format(const std::string& path) {
  if (path == "extreme") return CalibFormat::kExtreme;
  TLV_ASSIGN_OR_RETURN(const std::optional<datasets::DatasetFormat> dataset,
                       datasets::probe_dataset_format(path));
  if (dataset) return calib_format_of(*dataset);
  // Not a dataset. A dataset's layout without its index is an error naming the index: taking
  // its touch/ and vision/ images as a plain folder would silently change the data source.
  const fs::path p(path);
  std::error_code ec;
  const bool touch100k_layout =
      fs::is_directory(p / "touch", ec) || fs::is_directory(p / "vision", ec);
  TLV_ENSURE(!touch100k_layout, ErrorCode::kFormat,
             "%s: not found; '%s' has a Touch100k layout (touch/, vision/) but no index. To "
             "calibrate on its image files as a plain folder, pass --calib-images %s",
             (p / "data_list.json").c_str(), path.c_str(), path.c_str());
  for (const fs::directory_entry& e : fs::directory_iterator(p, ec)) {
    TLV_ENSURE(!fs::is_directory(e.path() / "gelsight_frame", ec), ErrorCode::kFormat,
               "%s: no train.txt / test.txt; '%s' has a Touch-and-Go layout "
               "(SESSION/gelsight_frame/) but no label files. To calibrate on its image files as "
               "a plain folder, pass --calib-images %s",
               path.c_str(), e.path().filename().c_str(), path.c_str());
  }
  bool any_image = false;
  for (const fs::directory_entry& e : fs::directory_iterator(p, ec)) {
    any_image =
        any_image ||
        (e.is_regular_file() && calib_sources::is_image_file(e.path().filename().string())) ||
        e.is_directory();
  }
  TLV_ENSURE(any_image, ErrorCode::kFormat,
             "cannot tell the format of '%s': no data_list.json (Touch100k), train.txt / test.txt "
             "(TAG), train_info.json / calandra_corl2017_*.h5 (Feel) or image files; use "
             "--calib-format",
             path.c_str());
  return CalibFormat::kImages;
}

namespace {

// One source: o.paths holds exactly it, the counts are its share.
Result<CalibData> load_source(const CalibDataOptions& o, const InputSpec& spec) {
  const std::string& path = o.paths.front();
  CalibData out;
  CalibFormat format = o.format;
  if (format == CalibFormat::kAuto) {
    TLV_ASSIGN_OR_RETURN(format, detect_calib_format(path));
  }
  out.formats = {format};
  if (format == CalibFormat::kExtreme) {
    TLV_ENSURE(o.split == datasets::Split::kAll, ErrorCode::kInvalidArgument,
               "the extreme set has no train/test split (use --calib-split all)");
    TLV_TRY(render_extreme(o, spec, out));
    return out;
  }
  auto listed = calib_sources::list_items(format, path, o.split, o.problems);
  if (!listed.ok()) return listed.error().with_context("%s", path.c_str());
  const std::vector<Item>& items = *listed;
  TLV_ENSURE(!items.empty(), ErrorCode::kFormat, "%s (%s): no frames found", path.c_str(),
             calib_format_name(format));
  const Selection sel = select(items, o);
  std::unordered_set<std::string> wanted = sel.calibration;
  wanted.insert(sel.heldout.begin(), sel.heldout.end());
  tools::Progress progress("quantize: reading frames", static_cast<int64_t>(wanted.size()), stderr,
                           o.progress ? tools::ProgressMode::kAuto : tools::ProgressMode::kQuiet);
  std::string load_summary;
  Status read = calib_sources::read_frames(
      format, path, wanted,
      [&](const Item& item, const tools::Image& image) -> Status {
        auto x = image::preprocess(image, spec);
        if (!x.ok()) return x.error().with_context("preprocessing %s", item.id().c_str());
        const bool calib = sel.calibration.count(item.id()) > 0;
        (calib ? out.calibration : out.heldout).push_back(std::move(x).value());
        (calib ? out.calibration_keys : out.heldout_keys).push_back(item.id());
        return {};
      },
      load_summary, [&] { progress.add(); }, o.on_note, o.problems);
  progress.finish();
  if (!read.ok()) return read.error().with_context("%s", path.c_str());
  TLV_ENSURE(!out.calibration.empty(), ErrorCode::kFormat,
             "%s: none of the %zu selected calibration frames could be loaded (%s)", path.c_str(),
             sel.calibration.size(), load_summary.c_str());
  out.summary = std::string(calib_format_name(format)) + " " + path + " (" +
                datasets::split_name(o.split) + " split): " + std::to_string(items.size()) +
                " frames in " + std::to_string(sel.groups) + " groups (" + load_summary +
                "); calibration " + std::to_string(out.calibration.size()) + " frames, held-out " +
                std::to_string(out.heldout.size()) + " frames from " +
                (sel.shared_group ? std::string("the same single group (no other exists)")
                                  : std::to_string(sel.heldout_groups) + " other groups") +
                ", seed " + std::to_string(o.seed);
  return out;
}

// A's frames and keys, then B's, ... -> A0 B0 A1 B1 ...: every prefix draws on every source.
void interleave(std::vector<CalibData>& parts, std::vector<std::vector<float>> CalibData::*frames,
                std::vector<std::string> CalibData::*keys, CalibData& out) {
  size_t longest = 0;
  for (const CalibData& p : parts) longest = std::max(longest, (p.*frames).size());
  for (size_t i = 0; i < longest; ++i) {
    for (CalibData& p : parts) {
      if (i >= (p.*frames).size()) continue;
      (out.*frames).push_back(std::move((p.*frames)[i]));
      (out.*keys).push_back(std::move((p.*keys)[i]));
    }
  }
}

}  // namespace

std::string calib_formats_name(const std::vector<CalibFormat>& formats) {
  std::string name;
  for (CalibFormat f : formats)
    name += (name.empty() ? "" : "+") + std::string(calib_format_name(f));
  return name;
}

Result<CalibData> load_calib_data(const CalibDataOptions& o, const InputSpec& spec) {
  TLV_ENSURE(o.calib_count >= 1 && o.calib_count <= kMaxCalibrationFrames && o.heldout_count >= 0 &&
                 o.heldout_count <= kMaxCalibrationFrames,
             ErrorCode::kInvalidArgument,
             "calibration count %lld / held-out count %lld outside 1..%lld / 0..%lld",
             static_cast<long long>(o.calib_count), static_cast<long long>(o.heldout_count),
             static_cast<long long>(kMaxCalibrationFrames),
             static_cast<long long>(kMaxCalibrationFrames));
  const auto sources = static_cast<int64_t>(o.paths.size());
  TLV_ENSURE(sources >= 1 && o.paths.size() <= kMaxCalibrationSources, ErrorCode::kInvalidArgument,
             "%zu calibration sources; 1..%zu are allowed", o.paths.size(), kMaxCalibrationSources);
  TLV_ENSURE(sources <= o.calib_count, ErrorCode::kInvalidArgument,
             "%lld calibration sources but %lld calibration frames: each source needs one",
             static_cast<long long>(sources), static_cast<long long>(o.calib_count));
  if (sources == 1) return load_source(o, spec);
  std::vector<CalibData> parts;
  for (int64_t k = 0; k < sources; ++k) {
    CalibDataOptions one = o;
    one.paths = {o.paths[static_cast<size_t>(k)]};
    one.calib_count = o.calib_count / sources + (k < o.calib_count % sources ? 1 : 0);
    one.heldout_count = o.heldout_count / sources + (k < o.heldout_count % sources ? 1 : 0);
    auto part = load_source(one, spec);
    if (!part.ok())
      return part.error().with_context("calibration source %lld of %lld",
                                       static_cast<long long>(k + 1),
                                       static_cast<long long>(sources));
    parts.push_back(std::move(part).value());
  }
  CalibData out;
  for (CalibData& p : parts) {
    out.formats.push_back(p.formats.front());
    out.summary += (out.summary.empty() ? "" : "\n") + p.summary;
  }
  interleave(parts, &CalibData::calibration, &CalibData::calibration_keys, out);
  interleave(parts, &CalibData::heldout, &CalibData::heldout_keys, out);
  return out;
}

Result<CalibrationStats> calibrate_frames(const Model& model,
                                          const std::vector<std::vector<float>>& frames,
                                          double averaging_constant, bool progress) {
  tools::Progress p("quantize: calibrating", static_cast<int64_t>(frames.size()), stderr,
                    progress ? tools::ProgressMode::kAuto : tools::ProgressMode::kQuiet);
  CalibrationRunOptions o;
  o.averaging_constant = averaging_constant;
  o.on_frame = [&p](uint64_t done) { p.set(static_cast<int64_t>(done)); };
  auto stats = calibrate(model, frames, o);
  p.finish();
  return stats;
}

}  // namespace tlvlink::quantize
