#include "feel_common.h"

#include "images.h"

namespace tlvlink::datasets {

std::string gelsight_key(int finger, int moment) {
  return std::string("gelsight") + kFingerNames[finger] + "_" + kMomentNames[moment];
}

std::string kinect_key(int moment) { return std::string("kinectA_rgb_") + kMomentNames[moment]; }

Status validate(const FeelWriterOptions& o) {
  TLV_TRY(validate(static_cast<const WriterOptions&>(o)));
  TLV_ENSURE(o.records_per_file >= 1 && o.records_per_file <= 10000, ErrorCode::kInvalidArgument,
             "records_per_file %d outside 1..10000", o.records_per_file);
  TLV_ENSURE(o.deflate_level >= 0 && o.deflate_level <= 9, ErrorCode::kInvalidArgument,
             "deflate_level %d outside 0..9", o.deflate_level);
  TLV_ENSURE(o.camera_jpeg_quality >= 0 && o.camera_jpeg_quality <= 100,
             ErrorCode::kInvalidArgument, "camera_jpeg_quality %d outside 0..100 (0 = none)",
             o.camera_jpeg_quality);
  TLV_ENSURE(o.gelsight_quarter_turns >= 0 && o.gelsight_quarter_turns <= 3,
             ErrorCode::kInvalidArgument, "gelsight_quarter_turns %d outside 0..3",
             o.gelsight_quarter_turns);
  return {};
}

Status check_episode(const GraspEpisode& e, bool need_vision) {
  TLV_ENSURE(!e.object_name.empty(), ErrorCode::kInvalidArgument,
             "grasp episode without an object_name");
  for (int f = 0; f < heads::kFingers; ++f)
    for (int m = 0; m < heads::kMoments; ++m)
      TLV_TRY(check_image(e.frames[f][m], e.object_name + " " + gelsight_key(f, m)));
  if (need_vision)
    for (int m = 0; m < heads::kMoments; ++m)
      TLV_TRY(check_image(e.vision[m], e.object_name + " " + kinect_key(m)));
  return {};
}

void reset_episode(GraspEpisode& e) {
  e.object_name.clear();
  e.object_id = -1;
  for (int32_t& k : e.sensor_instance) k = -1;  // unknown unless the metadata says
  e.sensor.clear();
  e.material = touch::MaterialSample{};
  e.material.class_id = -1;
  e.variables = GraspVariables{};
  e.is_gripping = false;
  for (auto& finger : e.states)
    for (auto& s : finger) s = touch::ContactState{};
}

}  // namespace tlvlink::datasets
