// Feel HDF5 writer: calandra_corl2017_NNN.h5 files of grasp record groups.

#include <cstdio>
#include <filesystem>

#include "feel_common.h"
#include "h5.h"
#include "images.h"
#include "line_io.h"
#include "meta.h"
#include "provenance.h"

namespace tlvlink::datasets {
namespace {

std::string feel_file_name(int32_t n) {
  char name[48];
  std::snprintf(name, sizeof name, "%s%03d.h5", kFeelFilePrefix, n);
  return name;
}

class FeelWriter final : public GraspDatasetWriter {
 public:
  FeelWriter(std::string dir, const FeelWriterOptions& options)
      : dir_(std::move(dir)), options_(options), splitter_(options.test_fraction) {}

  Status open() {
    TLV_ENSURE(!std::filesystem::exists(join_path(dir_, feel_file_name(0))),
               ErrorCode::kInvalidArgument, "%s already holds %s; write to an empty directory",
               dir_.c_str(), feel_file_name(0).c_str());
    h5::quiet();
    TLV_ENSURE(options_.deflate_level == 0 || H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0,
               ErrorCode::kInvalidArgument,
               "this HDF5 library has no deflate filter; use deflate_level 0");
    return make_dirs(dir_);
  }

  Status write(const GraspEpisode& e) override {
    TLV_ENSURE(!finished_, ErrorCode::kInvalidState, "%s: write after finish", dir_.c_str());
    TLV_TRY(check_episode(e, /*need_vision=*/true));
    const bool test = splitter_.is_test(e.object_name);
    if (!file_.valid() || in_file_ == options_.records_per_file) TLV_TRY(next_file());
    char group_name[16];
    std::snprintf(group_name, sizeof group_name, "%04d", in_file_);
    const std::string where = file_name_ + ":/" + group_name;
    h5::Handle group(H5Gcreate2(file_.get(), group_name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Gclose);
    TLV_ENSURE(group.valid(), ErrorCode::kIo, "%s: cannot create the record group: %s",
               where.c_str(), h5::last_error().c_str());
    TLV_TRY(h5::write_string(group.get(), "object_name", e.object_name, where + "/object_name"));
    TLV_TRY(
        h5::write_u8(group.get(), "is_gripping", e.is_gripping ? 1 : 0, where + "/is_gripping"));
    for (int f = 0; f < heads::kFingers; ++f) {
      for (int m = 0; m < heads::kMoments; ++m) {
        RgbImage image = e.frames[f][m];
        if (options_.camera_jpeg_quality > 0 && !options_.gelsight_live_path && !e.live_path)
          TLV_TRY(jpeg_round_trip(image, options_.camera_jpeg_quality));
        image = rotate_quarter_turns(image, options_.gelsight_quarter_turns);
        const std::string key = gelsight_key(f, m);
        TLV_TRY(h5::write_image(group.get(), key.c_str(), image, options_.deflate_level,
                                where + "/" + key));
      }
    }
    for (int m = 0; m < heads::kMoments; ++m) {
      RgbImage image = e.vision[m];
      if (options_.camera_jpeg_quality > 0)
        TLV_TRY(jpeg_round_trip(image, options_.camera_jpeg_quality));
      const std::string key = kinect_key(m);
      TLV_TRY(h5::write_image(group.get(), key.c_str(), image, options_.deflate_level,
                              where + "/" + key));
    }
    if (options_.sidecar) {
      TLV_TRY(h5::write_string_attribute(group.get(), "tlvlink_sim",
                                         grasp_meta(e, where, test).dump(), where));
    }
    ++in_file_;
    summary_.items += 1;
    (test ? summary_.test_items : summary_.train_items) += 1;
    return {};
  }

  Status finish() override {
    if (finished_) return {};
    finished_ = true;
    TLV_TRY(close_file());
    summary_.objects = splitter_.objects();
    summary_.test_objects = splitter_.test_objects();
    const OrderedJson extra = {
        {"records_per_file", options_.records_per_file},
        {"deflate_level", options_.deflate_level},
        {"camera_jpeg_quality", options_.camera_jpeg_quality},
        {"gelsight_quarter_turns", options_.gelsight_quarter_turns},
        {"record_layout", "/NNNN/{object_name,is_gripping,gelsight*,kinectA_rgb_*}"},
        {"split", "by object; recorded in each record's tlvlink_sim attribute"}};
    return write_provenance(dir_, "feel_hdf5", options_, extra, summary_);
  }

  const WriteSummary& summary() const override { return summary_; }

 private:
  Status next_file() {
    TLV_TRY(close_file());
    file_name_ = feel_file_name(file_count_++);
    file_path_ = join_path(dir_, file_name_);
    file_ = h5::Handle(H5Fcreate(file_path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                       H5Fclose);
    TLV_ENSURE(file_.valid(), ErrorCode::kIo, "%s: cannot create: %s", file_path_.c_str(),
               h5::last_error().c_str());
    in_file_ = 0;
    return {};
  }

  Status close_file() {
    if (!file_.valid()) return {};
    const herr_t rc = H5Fclose(file_.release());
    TLV_ENSURE(rc >= 0, ErrorCode::kIo, "%s: close failed: %s", file_path_.c_str(),
               h5::last_error().c_str());
    std::error_code ec;
    summary_.files += 1;
    summary_.bytes += static_cast<int64_t>(std::filesystem::file_size(file_path_, ec));
    return {};
  }

  std::string dir_;
  FeelWriterOptions options_;
  SplitAssigner splitter_;
  h5::Handle file_;
  std::string file_name_, file_path_;
  int32_t file_count_ = 0, in_file_ = 0;
  WriteSummary summary_;
  bool finished_ = false;
};

}  // namespace

Result<std::unique_ptr<GraspDatasetWriter>> create_feel_writer(const std::string& dir,
                                                               const FeelWriterOptions& options) {
  TLV_TRY(validate(options));
  auto writer = std::make_unique<FeelWriter>(dir, options);
  TLV_TRY(writer->open());
  return std::unique_ptr<GraspDatasetWriter>(std::move(writer));
}

}  // namespace tlvlink::datasets
