// Touch100k writer: touch/<img>, vision/<img>, data_list.json (+ sidecar, tlvlink_sim.json).

#include <filesystem>

#include "images.h"
#include "line_io.h"
#include "meta.h"
#include "provenance.h"
#include "tlvlink/datasets/touch100k.h"
#include "touch_common.h"

namespace tlvlink::datasets {
namespace {

class Touch100kWriter final : public TouchDatasetWriter {
 public:
  Touch100kWriter(std::string dir, const WriterOptions& options)
      : dir_(std::move(dir)), options_(options), splitter_(options.test_fraction) {}

  Status open() {
    TLV_ENSURE(!std::filesystem::exists(join_path(dir_, kTouch100kIndex)),
               ErrorCode::kInvalidArgument, "%s already holds a %s; write to an empty directory",
               dir_.c_str(), kTouch100kIndex);
    TLV_TRY(make_dirs(join_path(dir_, "touch")));
    TLV_TRY(make_dirs(join_path(dir_, "vision")));
    TLV_TRY(index_.open(join_path(dir_, kTouch100kIndex)));
    if (options_.sidecar) TLV_TRY(sidecar_.open(join_path(dir_, kTouch100kSidecar)));
    return {};
  }

  Status write(const TouchSample& s) override {
    TLV_ENSURE(!finished_, ErrorCode::kInvalidState, "%s: write after finish", dir_.c_str());
    TLV_TRY(check_touch_sample(s));
    TLV_ASSIGN_OR_RETURN(const bool test, splitter_.is_test(s));
    const std::string img = tag_frame_key(s.session, s.frame_index);
    if (s.session != last_session_) {
      TLV_TRY(make_dirs(join_path(dir_, "touch/" + s.session)));
      TLV_TRY(make_dirs(join_path(dir_, "vision/" + s.session)));
      last_session_ = s.session;
    }
    TLV_ASSIGN_OR_RETURN(const int64_t touch_bytes,
                         write_jpeg_image(join_path(dir_, "touch/" + img), s.touch,
                                          options_.jpeg_quality, options_.jpeg_full_chroma));
    TLV_ASSIGN_OR_RETURN(
        const int64_t vision_bytes,
        write_jpeg_image(join_path(dir_, "vision/" + img), s.vision, options_.jpeg_quality));
    const OrderedJson line = {
        {"img", img}, {"sentence_desc", s.sentence_desc}, {"phrase_desc", join_phrases(s.phrases)}};
    TLV_TRY(index_.write_line(line.dump()));
    if (options_.sidecar) TLV_TRY(sidecar_.write_line(touch_meta(s, img, test).dump()));
    summary_.items += 1;
    (test ? summary_.test_items : summary_.train_items) += 1;
    summary_.files += 2;
    summary_.bytes += touch_bytes + vision_bytes;
    return {};
  }

  Status finish() override {
    if (finished_) return {};
    finished_ = true;
    TLV_TRY(index_.close());
    TLV_TRY(sidecar_.close());
    summary_.files += options_.sidecar ? 2 : 1;
    summary_.bytes += index_.bytes() + sidecar_.bytes();
    splitter_.fill(summary_);
    return write_provenance(dir_, "touch100k", options_, OrderedJson::object(), summary_);
  }

  const WriteSummary& summary() const override { return summary_; }

 private:
  std::string dir_;
  WriterOptions options_;
  TouchSplitter splitter_;
  LineWriter index_, sidecar_;
  std::string last_session_;
  WriteSummary summary_;
  bool finished_ = false;
};

}  // namespace

Result<std::unique_ptr<TouchDatasetWriter>> create_touch100k_writer(const std::string& dir,
                                                                    const WriterOptions& options) {
  TLV_TRY(validate(options));
  auto writer = std::make_unique<Touch100kWriter>(dir, options);
  TLV_TRY(writer->open());
  return std::unique_ptr<TouchDatasetWriter>(std::move(writer));
}

}  // namespace tlvlink::datasets
