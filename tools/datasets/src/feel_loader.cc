// Feel HDF5 loader: streams the record groups of calandra_corl2017_*.h5, one file open at a time.

#include <algorithm>
#include <filesystem>

#include "feel_common.h"
#include "h5.h"
#include "images.h"
#include "line_io.h"
#include "meta.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::datasets {
namespace {

class FeelLoader final : public GraspEpisodeLoader {
 public:
  explicit FeelLoader(const FeelLoaderOptions& options)
      : options_(options), report_(options.max_kept_problems) {}

  Status open(const std::string& path) {
    h5::quiet();
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      for (const auto& entry : std::filesystem::directory_iterator(path, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(kFeelFilePrefix, 0) == 0 && entry.path().extension() == ".h5")
          files_.push_back(entry.path().string());
      }
      std::sort(files_.begin(), files_.end());
      TLV_ENSURE(!files_.empty(), ErrorCode::kIo, "%s: no %s*.h5 files", path.c_str(),
                 kFeelFilePrefix);
    } else {
      // A single file: opened (and, when broken, counted) by next() like any other; a FIFO or a
      // device given as the set is an error now (HDF5 would block opening a FIFO).
      if (std::filesystem::exists(path, ec)) TLV_TRY(RegularFile::open(path.c_str()));
      files_.push_back(path);
    }
    return {};
  }

  Result<bool> next(GraspEpisode& out) override {
    for (;;) {
      if (!file_.valid()) {
        if (file_index_ >= files_.size()) return false;
        open_next_file();
        continue;
      }
      if (group_index_ >= groups_.size()) {
        file_.reset();
        continue;
      }
      if (load_record(groups_[group_index_++], out)) {
        report_.count_loaded();
        return true;
      }
    }
  }

  const std::string& key() const override { return key_; }
  LoadReport& report() override { return report_; }

 private:
  void open_next_file() {
    path_ = files_[file_index_++];
    groups_.clear();
    group_index_ = 0;
    if (!std::filesystem::exists(path_)) {
      report_.add({ProblemKind::kMissingFile, path_, 0, "not found"});
      return;
    }
    // Checked first, non-blocking: HDF5's own open() of a FIFO never returns.
    if (auto regular = RegularFile::open(path_.c_str()); !regular.ok()) {
      report_.add({ProblemKind::kCorruptFile, path_, 0, regular.error().message()});
      return;
    }
    file_ = h5::Handle(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file_.valid()) {
      report_.add({ProblemKind::kCorruptFile, path_, 0,
                   "cannot open as HDF5 (truncated or not an HDF5 file): " + h5::last_error()});
      return;
    }
    auto groups = h5::root_groups(file_.get());
    if (!groups.ok()) {
      report_.add({ProblemKind::kCorruptFile, path_, 0, groups.error().message()});
      file_.reset();
      return;
    }
    groups_ = std::move(groups).value();
  }

  bool problem(ProblemKind kind, const std::string& record, const std::string& why) {
    report_.add({kind, path_, 0, "record /" + record + ": " + why});
    return false;
  }

  // Reads one image key: absent = malformed record, unreadable = corrupt file.
  bool read_image(hid_t group, const std::string& record, const std::string& key, RgbImage& out) {
    if (!h5::exists(group, key.c_str()))
      return problem(ProblemKind::kMalformedRecord, record, "no '" + key + "'");
    if (Status s = h5::read_image(group, key.c_str(), out); !s.ok())
      return problem(ProblemKind::kCorruptFile, record, s.error().message());
    return true;
  }

  bool load_record(const std::string& record, GraspEpisode& out) {
    h5::Handle group(H5Gopen2(file_.get(), record.c_str(), H5P_DEFAULT), H5Gclose);
    if (!group.valid()) return problem(ProblemKind::kCorruptFile, record, h5::last_error());
    auto name = h5::read_string(group.get(), "object_name");
    if (!name.ok()) return problem(ProblemKind::kMalformedRecord, record, name.error().message());
    Json meta;
    bool has_meta = false;
    if (h5::has_attribute(group.get(), "tlvlink_sim")) {
      auto text = h5::read_string_attribute(group.get(), "tlvlink_sim");
      std::string why;
      has_meta = text.ok() && parse_json(text.value(), meta, why) && meta.is_object();
      if (!has_meta)
        problem(ProblemKind::kSidecarMismatch, record,
                "tlvlink_sim attribute unreadable: " + (text.ok() ? why : text.error().message()));
    }
    if (options_.resplit) {
      if (!split_selects(options_.split, hash_split_is_test(name.value(), *options_.resplit)))
        return false;
    } else if (options_.split != Split::kAll) {
      const auto split = has_meta ? meta.find("split") : meta.end();
      if (!has_meta || split == meta.end() || !split->is_string())
        return problem(ProblemKind::kMalformedRecord, record,
                       "no recorded split (tlvlink_sim attribute); load with a resplit");
      if (!split_selects(options_.split, split->get<std::string>() == "test")) return false;
    }
    auto gripping = h5::read_integer(group.get(), "is_gripping");
    if (!gripping.ok())
      return problem(ProblemKind::kMalformedRecord, record, gripping.error().message());
    reset_episode(out);
    out.object_name = std::move(name).value();
    out.is_gripping = gripping.value() != 0;
    for (int f = 0; f < heads::kFingers; ++f) {
      for (int m = 0; m < heads::kMoments; ++m) {
        RgbImage& frame = out.frames[f][m];
        if (!options_.load_images) {
          frame = RgbImage{};
          continue;
        }
        if (!read_image(group.get(), record, gelsight_key(f, m), frame)) return false;
        if (options_.gelsight_quarter_turns != 0)
          frame = rotate_quarter_turns(frame, -options_.gelsight_quarter_turns);
      }
    }
    for (int m = 0; m < heads::kMoments; ++m) {
      const bool want = options_.load_images && options_.load_vision;
      if (want && !read_image(group.get(), record, kinect_key(m), out.vision[m])) {
        if (options_.require_vision) return false;
        out.vision[m] = RgbImage{};
      } else if (!want) {
        out.vision[m] = RgbImage{};
      }
    }
    std::string why;
    // The attribute carries the labels: a bad one drops the episode rather than score it wrong.
    if (has_meta && !apply_grasp_meta(meta, out, why)) {
      problem(ProblemKind::kMalformedRecord, record, "tlvlink_sim attribute: " + why);
      return false;
    }
    key_ = std::filesystem::path(path_).filename().string() + ":/" + record;
    return true;
  }

  FeelLoaderOptions options_;
  LoadReport report_;
  std::vector<std::string> files_;
  size_t file_index_ = 0;
  h5::Handle file_;
  std::string path_;
  std::vector<std::string> groups_;
  size_t group_index_ = 0;
  std::string key_;
};

Status validate_feel(const FeelLoaderOptions& options) {
  TLV_TRY(validate(static_cast<const LoaderOptions&>(options)));
  if (options.resplit) TLV_TRY(validate(*options.resplit));
  TLV_ENSURE(options.gelsight_quarter_turns >= 0 && options.gelsight_quarter_turns <= 3,
             ErrorCode::kInvalidArgument, "gelsight_quarter_turns %d outside 0..3",
             options.gelsight_quarter_turns);
  return {};
}

}  // namespace

Status validate(const FeelLoaderOptions& options) { return validate_feel(options); }

Result<std::unique_ptr<GraspEpisodeLoader>> open_feel(const std::string& path,
                                                      const FeelLoaderOptions& options) {
  TLV_TRY(validate_feel(options));
  auto loader = std::make_unique<FeelLoader>(options);
  TLV_TRY(loader->open(path));
  return std::unique_ptr<GraspEpisodeLoader>(std::move(loader));
}

}  // namespace tlvlink::datasets
