#pragma once
#ifndef TLVLINK_DATASETS_PRIVATE
#error "feel_common.h is internal to tools/datasets: include its public headers instead"
#endif
// Pieces the Feel HDF5 and repacked writers/loaders share. Internal.

#include <string>

#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/feel.h"

namespace tlvlink::datasets {

inline constexpr const char* kMomentNames[heads::kMoments] = {"before", "during", "after"};
inline constexpr const char* kFingerNames[heads::kFingers] = {"A", "B"};

std::string gelsight_key(int finger, int moment);  // "gelsightA_before"
std::string kinect_key(int moment);                // "kinectA_rgb_before"

Status validate(const FeelWriterOptions& options);
Status validate(const FeelLoaderOptions& options);
// Non-empty object name; GelSight frames (and the kinect images when need_vision) RGB.
Status check_episode(const GraspEpisode& episode, bool need_vision);
// Clears what a loaded episode does not overwrite, keeping the image buffers for reuse.
void reset_episode(GraspEpisode& episode);

}  // namespace tlvlink::datasets
