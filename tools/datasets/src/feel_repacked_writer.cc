// TLV-Link's repacked Feel layout: data/<touch_dir>/gelsight{A,B}_{before,during,after}.jpg and
// {train,test}_info.json JSON-lines (+ per-split sidecars, tlvlink_sim.json).

#include <cinttypes>
#include <cstdio>
#include <filesystem>

#include "feel_common.h"
#include "images.h"
#include "line_io.h"
#include "meta.h"
#include "provenance.h"

namespace tlvlink::datasets {
namespace {

class FeelRepackedWriter final : public GraspDatasetWriter {
 public:
  FeelRepackedWriter(std::string dir, const FeelWriterOptions& options)
      : dir_(std::move(dir)), options_(options), splitter_(options.test_fraction) {}

  Status open() {
    TLV_ENSURE(!std::filesystem::exists(join_path(dir_, "train_info.json")),
               ErrorCode::kInvalidArgument,
               "%s already holds a train_info.json; write to an empty directory", dir_.c_str());
    TLV_TRY(make_dirs(join_path(dir_, "data")));
    TLV_TRY(train_.open(join_path(dir_, "train_info.json")));
    TLV_TRY(test_.open(join_path(dir_, "test_info.json")));
    if (options_.sidecar) {
      TLV_TRY(train_sidecar_.open(join_path(dir_, "tlvlink_sim_train.jsonl")));
      TLV_TRY(test_sidecar_.open(join_path(dir_, "tlvlink_sim_test.jsonl")));
    }
    return {};
  }

  Status write(const GraspEpisode& e) override {
    TLV_ENSURE(!finished_, ErrorCode::kInvalidState, "%s: write after finish", dir_.c_str());
    TLV_TRY(check_episode(e, /*need_vision=*/false));
    TLV_ENSURE(is_safe_name(e.object_name), ErrorCode::kInvalidArgument,
               "object_name '%s' is not a safe folder name (letters, digits, _-.)",
               e.object_name.c_str());
    const bool test = splitter_.is_test(e.object_name);
    char number[24];
    std::snprintf(number, sizeof number, "_%06" PRId64, summary_.items);
    const std::string touch_dir = e.object_name + number;
    TLV_TRY(make_dirs(join_path(dir_, "data/" + touch_dir)));
    for (int f = 0; f < heads::kFingers; ++f) {
      for (int m = 0; m < heads::kMoments; ++m) {
        RgbImage image = e.frames[f][m];
        if (options_.camera_jpeg_quality > 0 && !options_.gelsight_live_path && !e.live_path)
          TLV_TRY(jpeg_round_trip(image, options_.camera_jpeg_quality));
        const std::string path =
            join_path(dir_, "data/" + touch_dir + "/" + gelsight_key(f, m) + ".jpg");
        TLV_ASSIGN_OR_RETURN(
            const int64_t bytes,
            write_jpeg_image(path, image, options_.jpeg_quality, options_.jpeg_full_chroma));
        summary_.bytes += bytes;
        summary_.files += 1;
      }
    }
    const OrderedJson info = {
        {"object", e.object_name}, {"touch_dir", touch_dir}, {"grasping", e.is_gripping}};
    TLV_TRY((test ? test_ : train_).write_line(info.dump()));
    if (options_.sidecar)
      TLV_TRY((test ? test_sidecar_ : train_sidecar_)
                  .write_line(grasp_meta(e, touch_dir, test).dump()));
    summary_.items += 1;
    (test ? summary_.test_items : summary_.train_items) += 1;
    return {};
  }

  Status finish() override {
    if (finished_) return {};
    finished_ = true;
    for (LineWriter* w : {&train_, &test_, &train_sidecar_, &test_sidecar_}) {
      if (!w->is_open()) continue;
      TLV_TRY(w->close());
      summary_.files += 1;
      summary_.bytes += w->bytes();
    }
    summary_.objects = splitter_.objects();
    summary_.test_objects = splitter_.test_objects();
    const OrderedJson extra = {{"camera_jpeg_quality", options_.camera_jpeg_quality},
                               {"touch_dir", "<object_name>_<NNNNNN>"},
                               {"split", "by object"}};
    return write_provenance(dir_, "feel_repacked", options_, extra, summary_);
  }

  const WriteSummary& summary() const override { return summary_; }

 private:
  std::string dir_;
  FeelWriterOptions options_;
  SplitAssigner splitter_;
  LineWriter train_, test_, train_sidecar_, test_sidecar_;
  WriteSummary summary_;
  bool finished_ = false;
};

}  // namespace

Result<std::unique_ptr<GraspDatasetWriter>> create_feel_repacked_writer(
    const std::string& dir, const FeelWriterOptions& options) {
  TLV_TRY(validate(options));
  auto writer = std::make_unique<FeelRepackedWriter>(dir, options);
  TLV_TRY(writer->open());
  return std::unique_ptr<GraspDatasetWriter>(std::move(writer));
}

}  // namespace tlvlink::datasets
