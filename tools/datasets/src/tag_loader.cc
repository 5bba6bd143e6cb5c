// Touch-and-Go loader: streams the material label file(s), joins the hard/rough labels and
// reads each frame's images as it goes.

#include <filesystem>
#include <unordered_map>
#include <vector>

#include "images.h"
#include "line_io.h"
#include "meta.h"
#include "tlvlink/datasets/touch_and_go.h"

namespace tlvlink::datasets {
namespace {

// Touch-and-Go's soft classes: leather, synthetic fabric, natural fabric, paper, grass.
bool class_is_soft(int32_t id) { return id == 7 || id == 8 || id == 9 || id == 11 || id == 13; }

// "train.txt" -> "tlvlink_sim_train.jsonl"
std::string sidecar_name(const std::string& label_file) {
  return "tlvlink_sim_" + std::filesystem::path(label_file).stem().string() + ".jsonl";
}

class TagLoader final : public TouchSampleLoader {
 public:
  TagLoader(std::string dir, const TagLoaderOptions& options)
      : dir_(std::move(dir)), options_(options), report_(options.max_kept_problems) {}

  Status open() {
    const TagLayout& l = options_.layout;
    const bool train = options_.resplit || options_.split != Split::kTest;
    const bool test = options_.resplit || options_.split != Split::kTrain;
    if (train) {
      material_files_.push_back(l.material_train);
      read_labels(l.hard_train, hard_);
      read_labels(l.rough_train, rough_);
    }
    if (test) {
      material_files_.push_back(l.material_test);
      read_labels(l.hard_test, hard_);
      read_labels(l.rough_test, rough_);
    }
    for (const std::string& f : material_files_) {
      TLV_ENSURE(std::filesystem::exists(join_path(dir_, f)), ErrorCode::kIo,
                 "%s: material label file not found", join_path(dir_, f).c_str());
    }
    return open_file(0);
  }

  Result<bool> next(TouchSample& out) override {
    while (file_ < material_files_.size()) {
      std::string line;
      while (labels_.next(line)) {
        if (is_blank(line)) continue;
        if (load_line(line, out)) {
          report_.count_loaded();
          return true;
        }
      }
      if (++file_ < material_files_.size()) TLV_TRY(open_file(file_));
    }
    return false;
  }

  const std::string& key() const override { return key_; }
  LoadReport& report() override { return report_; }

 private:
  Status open_file(size_t i) {
    TLV_TRY(labels_.open(join_path(dir_, material_files_[i])));
    sidecar_ = SidecarReader();
    if (options_.use_sidecar) sidecar_.open(join_path(dir_, sidecar_name(material_files_[i])));
    return {};
  }

  // Reads a 0/1 label file into `map`; an absent file is allowed (labels then unknown).
  void read_labels(const std::string& name, std::unordered_map<std::string, int8_t>& map) {
    LineReader r;
    if (!std::filesystem::exists(join_path(dir_, name)) || !r.open(join_path(dir_, name)).ok())
      return;
    std::string line;
    while (r.next(line)) {
      if (is_blank(line)) continue;
      auto parsed = parse_tag_label_line(line);
      std::string why;
      if (!parsed.ok()) {
        why = parsed.error().message();
      } else if (parsed->label != 0 && parsed->label != 1) {
        why = "label " + std::to_string(parsed->label) + " is not 0 or 1";
      }
      if (!why.empty()) {
        report_.add({ProblemKind::kMalformedLine, r.path(), r.line_number(), why});
        continue;
      }
      map[parsed->key] = static_cast<int8_t>(parsed->label);
    }
  }

  bool malformed(const std::string& why) {
    report_.add({ProblemKind::kMalformedLine, labels_.path(), labels_.line_number(), why});
    sidecar_.skip();
    return false;
  }

  bool load_line(const std::string& line, TouchSample& out) {
    auto parsed = parse_tag_label_line(line);
    if (!parsed.ok()) return malformed(parsed.error().message());
    TagLabelLine& l = parsed.value();
    if (l.label < 0 || l.label >= touch::kMaterialClassCount)
      return malformed("material id " + std::to_string(l.label) + " outside 0..19");
    const Json* meta = sidecar_.next(l.key, report_);
    if (options_.resplit &&
        !split_selects(options_.split, hash_split_is_test(l.session, *options_.resplit)))
      return false;
    out.session = l.session;
    out.frame_index = l.frame_index;
    out.object_id = -1;
    out.sensor_instance = -1;  // unknown unless the sidecar says
    out.material = touch::MaterialSample{};
    out.material.class_id = l.label;
    const auto hard = hard_.find(l.key);
    out.material.hard = hard != hard_.end() ? hard->second == 1 : !class_is_soft(l.label);
    const auto rough = rough_.find(l.key);
    out.material.rough = rough != rough_.end() ? rough->second : -1;
    out.contact = touch::ContactState{};
    out.sentence_desc.clear();
    out.phrases.clear();
    const std::string frame = l.key.substr(l.session.size() + 1);
    if (!options_.load_images) {
      out.touch = RgbImage{};
      out.vision = RgbImage{};
    } else {
      if (!load_jpeg_image(join_path(dir_, l.session + "/gelsight_frame/" + frame),
                           options_.scale_denominator, out.touch, report_))
        return false;
      const bool vision_ok = options_.load_vision &&
                             load_jpeg_image(join_path(dir_, l.session + "/video_frame/" + frame),
                                             options_.scale_denominator, out.vision, report_);
      if (options_.load_vision && !vision_ok && options_.require_vision) return false;
      if (!vision_ok) out.vision = RgbImage{};
    }
    std::string why;
    if (meta != nullptr) {
      // The labels stay those of the label files; the sidecar adds physics and contact.
      const touch::MaterialSample labels = out.material;
      if (apply_touch_meta(*meta, out, why)) {
        out.material.class_id = labels.class_id;
        out.material.hard = labels.hard;
        out.material.rough = labels.rough;
      } else {
        report_.add({ProblemKind::kSidecarMismatch, sidecar_.path(), sidecar_.line_number(),
                     l.key + ": " + why});
      }
    }
    key_ = l.key;
    return true;
  }

  std::string dir_;
  TagLoaderOptions options_;
  LoadReport report_;
  std::vector<std::string> material_files_;
  size_t file_ = 0;
  std::unordered_map<std::string, int8_t> hard_, rough_;
  LineReader labels_;
  SidecarReader sidecar_;
  std::string key_;
};

}  // namespace

Result<std::unique_ptr<TouchSampleLoader>> open_touch_and_go(const std::string& dir,
                                                             const TagLoaderOptions& options) {
  TLV_TRY(validate(static_cast<const LoaderOptions&>(options)));
  if (options.resplit) TLV_TRY(validate(*options.resplit));
  auto loader = std::make_unique<TagLoader>(dir, options);
  TLV_TRY(loader->open());
  return std::unique_ptr<TouchSampleLoader>(std::move(loader));
}

}  // namespace tlvlink::datasets
