// Touch100k loader: streams data_list.json, reading each sample's images as it goes.

#include "images.h"
#include "line_io.h"
#include "meta.h"
#include "tlvlink/datasets/touch100k.h"
#include "touch_common.h"

namespace tlvlink::datasets {

Status validate(const LoaderOptions& o) {
  TLV_ENSURE(o.scale_denominator == 1 || o.scale_denominator == 2 || o.scale_denominator == 4 ||
                 o.scale_denominator == 8,
             ErrorCode::kInvalidArgument, "scale_denominator %d is not 1, 2, 4 or 8",
             o.scale_denominator);
  return {};
}

namespace {

// Resets what a loaded sample does not overwrite, keeping the image buffers for reuse.
void reset_touch(TouchSample& s) {
  s.session.clear();
  s.frame_index = -1;
  s.object_id = -1;
  s.sensor_instance = -1;  // unknown unless the sidecar says
  s.material = touch::MaterialSample{};
  s.material.class_id = -1;
  s.contact = touch::ContactState{};
  s.sentence_desc.clear();
  s.phrases.clear();
}

class Touch100kLoader final : public TouchSampleLoader {
 public:
  Touch100kLoader(std::string dir, const Touch100kLoaderOptions& options)
      : dir_(std::move(dir)), options_(options), report_(options.max_kept_problems) {}

  Status open() {
    TLV_TRY(index_.open(join_path(dir_, kTouch100kIndex)));
    if (options_.use_sidecar) sidecar_.open(join_path(dir_, kTouch100kSidecar));
    return {};
  }

  Result<bool> next(TouchSample& out) override {
    std::string line;
    while (index_.next(line)) {
      if (is_blank(line)) continue;
      if (load_line(line, out)) {
        report_.count_loaded();
        return true;
      }
    }
    return false;
  }

  const std::string& key() const override { return key_; }
  Split recorded_split() const override { return recorded_split_; }
  LoadReport& report() override { return report_; }

 private:
  // Counts a malformed index line; returns false (the line yields no sample).
  bool malformed(const std::string& why) {
    report_.add({ProblemKind::kMalformedLine, index_.path(), index_.line_number(), why});
    sidecar_.skip();
    return false;
  }

  // "split": "train" | "test" of a sidecar line; anything else is counted and reads as unrecorded.
  Split sidecar_split(const Json& meta, const std::string& name) {
    const auto split = meta.find("split");
    if (split != meta.end() && split->is_string()) {
      if (*split == "train") return Split::kTrain;
      if (*split == "test") return Split::kTest;
    }
    report_.add({ProblemKind::kSidecarMismatch, kTouch100kSidecar, 0,
                 name + ": no \"split\" of \"train\" or \"test\""});
    return Split::kAll;
  }

  bool load_line(const std::string& line, TouchSample& out) {
    if (line.size() > kMaxLineBytes) {
      return malformed("line longer than " + std::to_string(kMaxLineBytes) + " bytes");
    }
    Json j;
    std::string why;
    if (!parse_json(line, j, why)) return malformed(why);
    if (!j.is_object()) return malformed("not a JSON object");
    const auto img = j.find("img");
    const auto sentence = j.find("sentence_desc");
    const auto phrase = j.find("phrase_desc");
    if (img == j.end() || !img->is_string()) return malformed("no string \"img\"");
    if (sentence == j.end() || !sentence->is_string())
      return malformed("no string \"sentence_desc\"");
    if (phrase == j.end() || !(phrase->is_string() || phrase->is_array()))
      return malformed("no \"phrase_desc\" (string or array of strings)");
    const std::string name = img->get<std::string>();
    if (!is_safe_relative_path(name))
      return malformed("img '" + name + "' is not a relative path inside the set");
    std::vector<std::string> phrases;
    if (phrase->is_string()) {
      phrases = split_phrases(phrase->get<std::string>());
    } else {
      for (const Json& p : *phrase) {
        if (!p.is_string()) return malformed("phrase_desc array holds a non-string");
        phrases.push_back(std::string(trim(p.get<std::string>())));
      }
    }
    const Json* meta = sidecar_.next(name, report_);
    reset_touch(out);
    if (!options_.load_images) {
      out.touch = RgbImage{};
      out.vision = RgbImage{};
    } else {
      if (!load_jpeg_image(join_path(dir_, "touch/" + name), options_.scale_denominator, out.touch,
                           report_))
        return false;
      if (options_.load_vision) {
        if (!load_jpeg_image(join_path(dir_, "vision/" + name), options_.scale_denominator,
                             out.vision, report_)) {
          if (options_.require_vision) return false;
          out.vision = RgbImage{};
        }
      } else {
        out.vision = RgbImage{};
      }
    }
    if (!parse_tag_frame_key(name, out.session, out.frame_index)) out.session = name;
    out.sentence_desc = sentence->get<std::string>();
    out.phrases = std::move(phrases);
    // The sidecar carries the labels: a bad line drops the sample rather than score it wrong.
    if (meta != nullptr && !apply_touch_meta(*meta, out, why)) {
      report_.add({ProblemKind::kMalformedLine, sidecar_.path(), sidecar_.line_number(),
                   name + ": " + why});
      return false;
    }
    recorded_split_ = meta != nullptr ? sidecar_split(*meta, name) : Split::kAll;
    key_ = name;
    return true;
  }

  std::string dir_;
  Touch100kLoaderOptions options_;
  LoadReport report_;
  LineReader index_;
  SidecarReader sidecar_;
  std::string key_;
  Split recorded_split_ = Split::kAll;
};

}  // namespace

Result<std::unique_ptr<TouchSampleLoader>> open_touch100k(const std::string& dir,
                                                          const Touch100kLoaderOptions& options) {
  TLV_TRY(validate(static_cast<const LoaderOptions&>(options)));
  auto loader = std::make_unique<Touch100kLoader>(dir, options);
  TLV_TRY(loader->open());
  return std::unique_ptr<TouchSampleLoader>(std::move(loader));
}

}  // namespace tlvlink::datasets
