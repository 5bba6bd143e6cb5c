// Loader of TLV-Link's repacked Feel layout: streams {train,test}_info.json.

#include <filesystem>

#include "feel_common.h"
#include "images.h"
#include "line_io.h"
#include "meta.h"

namespace tlvlink::datasets {
namespace {

class FeelRepackedLoader final : public GraspEpisodeLoader {
 public:
  FeelRepackedLoader(std::string dir, const FeelLoaderOptions& options)
      : dir_(std::move(dir)), options_(options), report_(options.max_kept_problems) {}

  Status open() {
    if (options_.resplit || options_.split != Split::kTest) splits_.push_back("train");
    if (options_.resplit || options_.split != Split::kTrain) splits_.push_back("test");
    for (const std::string& s : splits_) {
      const std::string path = join_path(dir_, s + "_info.json");
      TLV_ENSURE(std::filesystem::exists(path), ErrorCode::kIo, "%s: info file not found",
                 path.c_str());
    }
    return open_split(0);
  }

  Result<bool> next(GraspEpisode& out) override {
    while (split_ < splits_.size()) {
      std::string line;
      while (info_.next(line)) {
        if (is_blank(line)) continue;
        if (load_line(line, out)) {
          report_.count_loaded();
          return true;
        }
      }
      if (++split_ < splits_.size()) TLV_TRY(open_split(split_));
    }
    return false;
  }

  const std::string& key() const override { return key_; }
  LoadReport& report() override { return report_; }

 private:
  Status open_split(size_t i) {
    TLV_TRY(info_.open(join_path(dir_, splits_[i] + "_info.json")));
    sidecar_ = SidecarReader();
    if (options_.use_sidecar)
      sidecar_.open(join_path(dir_, "tlvlink_sim_" + splits_[i] + ".jsonl"));
    return {};
  }

  bool malformed(const std::string& why) {
    report_.add({ProblemKind::kMalformedLine, info_.path(), info_.line_number(), why});
    sidecar_.skip();
    return false;
  }

  bool load_line(const std::string& line, GraspEpisode& out) {
    if (line.size() > kMaxLineBytes) return malformed("line too long");
    Json j;
    std::string why;
    if (!parse_json(line, j, why)) return malformed(why);
    if (!j.is_object()) return malformed("not a JSON object");
    const auto object = j.find("object");
    const auto touch_dir = j.find("touch_dir");
    const auto grasping = j.find("grasping");
    if (object == j.end() || !object->is_string()) return malformed("no string \"object\"");
    if (touch_dir == j.end() || !touch_dir->is_string())
      return malformed("no string \"touch_dir\"");
    bool gripping = false;
    if (grasping != j.end() && grasping->is_boolean()) {
      gripping = grasping->get<bool>();
    } else if (grasping != j.end() && grasping->is_number_integer() &&
               (grasping->get<int64_t>() == 0 || grasping->get<int64_t>() == 1)) {
      gripping = grasping->get<int64_t>() == 1;
    } else {
      return malformed("\"grasping\" is not true/false or 0/1");
    }
    const std::string dir = touch_dir->get<std::string>();
    if (!is_safe_relative_path(dir))
      return malformed("touch_dir '" + dir + "' is not a relative path inside the set");
    const Json* meta = sidecar_.next(dir, report_);
    const std::string name = object->get<std::string>();
    if (options_.resplit &&
        !split_selects(options_.split, hash_split_is_test(name, *options_.resplit)))
      return false;
    reset_episode(out);
    out.object_name = name;
    out.is_gripping = gripping;
    for (int f = 0; f < heads::kFingers; ++f) {
      for (int m = 0; m < heads::kMoments; ++m) {
        RgbImage& frame = out.frames[f][m];
        if (!options_.load_images) {
          frame = RgbImage{};
          continue;
        }
        const std::string path = join_path(dir_, "data/" + dir + "/" + gelsight_key(f, m) + ".jpg");
        if (!load_jpeg_image(path, options_.scale_denominator, frame, report_)) return false;
      }
    }
    for (auto& v : out.vision) v = RgbImage{};  // the repacked layout has no camera images
    // The sidecar carries the labels: a bad line drops the episode rather than score it wrong.
    if (meta != nullptr && !apply_grasp_meta(*meta, out, why)) {
      report_.add(
          {ProblemKind::kMalformedLine, sidecar_.path(), sidecar_.line_number(), dir + ": " + why});
      return false;
    }
    key_ = dir;
    return true;
  }

  std::string dir_;
  FeelLoaderOptions options_;
  LoadReport report_;
  std::vector<std::string> splits_;
  size_t split_ = 0;
  LineReader info_;
  SidecarReader sidecar_;
  std::string key_;
};

}  // namespace

Result<std::unique_ptr<GraspEpisodeLoader>> open_feel_repacked(const std::string& dir,
                                                               const FeelLoaderOptions& options) {
  TLV_TRY(validate(options));
  auto loader = std::make_unique<FeelRepackedLoader>(dir, options);
  TLV_TRY(loader->open());
  return std::unique_ptr<GraspEpisodeLoader>(std::move(loader));
}

}  // namespace tlvlink::datasets
