#pragma once
// The records of a dataset, format-independent: what the dataset writers (Touch100k,
// Touch-and-Go, Feel) store and what the loaders give back, from real or simulated sets. The
// simulator writes them (sim/dataset.h names them under sim::); it does not own them.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/touch/contact_state.h"
#include "tlvlink/touch/materials.h"

namespace tlvlink::datasets {

struct RgbImage {
  int32_t height = 0, width = 0;
  std::vector<uint8_t> rgb;  // height * width * 3
};

// One touch frame of a session (Touch100k / Touch-and-Go). A session is one object touched
// several times; sessions never straddle a train/test split.
struct TouchSample {
  std::string session;      // "YYYYMMDD_HHMMSS", unique per session
  int32_t frame_index = 0;  // within the session
  int32_t object_id = 0;    // one object per session
  // The simulated sensor the session was recorded on, 0..sensor_instances-1 (sim/generate.h); the
  // same for every frame of a session. Loaders: 0 from sidecars written before the field
  // existed (those sets used one instance), -1 when there is no simulator metadata.
  int32_t sensor_instance = 0;
  // The sensor profile the session was recorded on ("gelsight-mini"); empty when the data does
  // not say (loaders of sets written before it was recorded, real data).
  std::string sensor;
  touch::MaterialSample material;
  touch::ContactState contact;
  RgbImage touch;                    // the GelSight frame
  RgbImage vision;                   // the paired camera image of the object
  std::string sentence_desc;         // sentence-level tactile description
  std::vector<std::string> phrases;  // phrase-level description (phrase_desc = join ", ")
};

// The fingers and moments of a grasp are the heads' (runtime/heads): a real Feel episode and a
// simulated one are read by the same grasp head.
using heads::kFingers;
using heads::kMoments;
using heads::Moment;

// The variables of one grasp. Visible ones can be estimated from before+during frames;
// hidden ones (mass, centre-of-mass offset, lift acceleration) cannot.
struct GraspVariables {
  // visible
  double grip_force_n = 0;  // P, integer 5..35 N as in Feel
  double friction = 0;      // mu, from the material
  double contact_area_mm2[kFingers] = {0, 0};
  bool finger_in_contact[kFingers] = {true, true};
  // hidden
  double mass_kg = 0;
  double com_offset_mm = 0;
  double lift_accel_mps2 = 0;
  // outcome
  double slip_ratio = 0;  // rho at the lift (max over fingers)
  double margin = 0;      // 1 - rho
};

struct GraspEpisode {
  std::string object_name;  // unique per object; splits are by object
  int32_t object_id = 0;
  // The simulated sensor of each finger ([gelsightA, gelsightB]), as TouchSample's.
  int32_t sensor_instance[kFingers] = {0, 0};
  std::string sensor;  // the profile both fingers carry ("" = not recorded)
  touch::MaterialSample material;
  GraspVariables variables;
  bool is_gripping = false;             // label: still held after the lift
  bool live_path = false;               // the tactile frames went through the sensor's live path
  RgbImage frames[kFingers][kMoments];  // [finger][heads::Moment]
  touch::ContactState states[kFingers][kMoments];
  RgbImage vision[kMoments];  // kinectA_rgb_{before,during,after} stand-in
};

}  // namespace tlvlink::datasets
