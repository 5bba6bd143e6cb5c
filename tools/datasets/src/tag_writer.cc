// Touch-and-Go writer: session folders of gelsight_frame/ and video_frame/ JPEGs, material /
// hard / rough label files per split (+ per-split sidecars, tlvlink_sim.json).

#include <filesystem>

#include "images.h"
#include "line_io.h"
#include "meta.h"
#include "provenance.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "touch_common.h"

namespace tlvlink::datasets {
namespace {

// The label files (and sidecar) of one split.
struct SplitFiles {
  LineWriter material, hard, rough, sidecar;
  Status open(const std::string& dir, const std::string& m, const std::string& h,
              const std::string& r, const std::string& side, bool with_sidecar) {
    TLV_TRY(material.open(join_path(dir, m)));
    TLV_TRY(hard.open(join_path(dir, h)));
    TLV_TRY(rough.open(join_path(dir, r)));
    if (with_sidecar) TLV_TRY(sidecar.open(join_path(dir, side)));
    return {};
  }
  Status close(WriteSummary& summary) {
    for (LineWriter* w : {&material, &hard, &rough, &sidecar}) {
      if (!w->is_open()) continue;
      TLV_TRY(w->close());
      summary.files += 1;
      summary.bytes += w->bytes();
    }
    return {};
  }
};

class TagWriter final : public TouchDatasetWriter {
 public:
  TagWriter(std::string dir, const WriterOptions& options)
      : dir_(std::move(dir)), options_(options), splitter_(options.test_fraction) {}

  Status open() {
    TLV_ENSURE(!std::filesystem::exists(join_path(dir_, layout_.material_train)),
               ErrorCode::kInvalidArgument, "%s already holds a %s; write to an empty directory",
               dir_.c_str(), layout_.material_train.c_str());
    TLV_TRY(make_dirs(dir_));
    TLV_TRY(train_.open(dir_, layout_.material_train, layout_.hard_train, layout_.rough_train,
                        "tlvlink_sim_train.jsonl", options_.sidecar));
    TLV_TRY(test_.open(dir_, layout_.material_test, layout_.hard_test, layout_.rough_test,
                       "tlvlink_sim_test.jsonl", options_.sidecar));
    return {};
  }

  Status write(const TouchSample& s) override {
    TLV_ENSURE(!finished_, ErrorCode::kInvalidState, "%s: write after finish", dir_.c_str());
    TLV_TRY(check_touch_sample(s));
    TLV_ENSURE(s.material.class_id >= 0 && s.material.class_id < touch::kMaterialClassCount,
               ErrorCode::kInvalidArgument, "touch sample %s/%d: material class %d outside 0..%d",
               s.session.c_str(), s.frame_index, s.material.class_id,
               touch::kMaterialClassCount - 1);
    TLV_ASSIGN_OR_RETURN(const bool test, splitter_.is_test(s));
    if (s.session != last_session_) {
      TLV_TRY(make_dirs(join_path(dir_, s.session + "/gelsight_frame")));
      TLV_TRY(make_dirs(join_path(dir_, s.session + "/video_frame")));
      last_session_ = s.session;
    }
    const std::string key = tag_frame_key(s.session, s.frame_index);
    const std::string file = key.substr(s.session.size() + 1);
    TLV_ASSIGN_OR_RETURN(
        const int64_t touch_bytes,
        write_jpeg_image(join_path(dir_, s.session + "/gelsight_frame/" + file), s.touch,
                         options_.jpeg_quality, options_.jpeg_full_chroma));
    TLV_ASSIGN_OR_RETURN(const int64_t vision_bytes,
                         write_jpeg_image(join_path(dir_, s.session + "/video_frame/" + file),
                                          s.vision, options_.jpeg_quality));
    SplitFiles& f = test ? test_ : train_;
    TLV_TRY(f.material.write_line(key + "," + std::to_string(s.material.class_id)));
    TLV_TRY(f.hard.write_line(key + (s.material.hard ? ",1" : ",0")));
    if (s.material.rough >= 0) TLV_TRY(f.rough.write_line(key + (s.material.rough ? ",1" : ",0")));
    if (options_.sidecar) TLV_TRY(f.sidecar.write_line(touch_meta(s, key, test).dump()));
    summary_.items += 1;
    (test ? summary_.test_items : summary_.train_items) += 1;
    summary_.files += 2;
    summary_.bytes += touch_bytes + vision_bytes;
    return {};
  }

  Status finish() override {
    if (finished_) return {};
    finished_ = true;
    TLV_TRY(train_.close(summary_));
    TLV_TRY(test_.close(summary_));
    splitter_.fill(summary_);
    const OrderedJson extra = {{"label_files",
                                {{"material", {layout_.material_train, layout_.material_test}},
                                 {"hard", {layout_.hard_train, layout_.hard_test}},
                                 {"rough", {layout_.rough_train, layout_.rough_test}}}},
                               {"split", "by object/session"}};
    return write_provenance(dir_, "touch_and_go", options_, extra, summary_);
  }

  const WriteSummary& summary() const override { return summary_; }

 private:
  std::string dir_;
  WriterOptions options_;
  TagLayout layout_;
  TouchSplitter splitter_;
  SplitFiles train_, test_;
  std::string last_session_;
  WriteSummary summary_;
  bool finished_ = false;
};

}  // namespace

Result<std::unique_ptr<TouchDatasetWriter>> create_tag_writer(const std::string& dir,
                                                              const WriterOptions& options) {
  TLV_TRY(validate(options));
  auto writer = std::make_unique<TagWriter>(dir, options);
  TLV_TRY(writer->open());
  return std::unique_ptr<TouchDatasetWriter>(std::move(writer));
}

}  // namespace tlvlink::datasets
