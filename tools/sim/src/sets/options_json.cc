// The generators' options as the JSON objects a dataset's tlvlink_sim.json records (sets.h).

#include <string>

#include <nlohmann/json.hpp>

#include "tlvlink/sim/sets.h"

namespace tlvlink::sim {

using OrderedJson = nlohmann::ordered_json;

std::string touch_set_options_json(const TouchSetOptions& o) {
  OrderedJson j = {{"generator", "TouchSampleGenerator"},
                   {"sessions", o.sessions},
                   {"frames_per_session", o.frames_per_session},
                   {"sensor", std::string(o.sensor)},
                   {"vision_height", o.vision_height},
                   {"vision_width", o.vision_width},
                   {"markers", o.markers},
                   {"markers_fraction", o.markers_fraction},
                   {"seed", o.seed},
                   {"sensor_instances", o.sensor_instances}};
  return j.dump();
}

std::string grasp_set_options_json(const GraspSetOptions& o) {
  OrderedJson j = {{"generator", "GraspEpisodeGenerator"},
                   {"objects", o.objects},
                   {"grasps_per_object", o.grasps_per_object},
                   {"sensor", std::string(o.sensor)},
                   {"vision_height", o.vision_height},
                   {"vision_width", o.vision_width},
                   {"markers", o.markers},
                   {"markers_fraction", o.markers_fraction},
                   {"live_path", o.live_path},
                   {"live_path_fraction", o.live_path_fraction},
                   {"seed", o.seed},
                   {"sensor_instances", o.sensor_instances}};
  return j.dump();
}

}  // namespace tlvlink::sim
