#pragma once
// The dataset records the simulator generates (tools/datasets owns them: records.h), named under
// sim:: for the generators. Generation is seeded and streaming: a generator yields one item at a
// time and never holds the dataset in memory (generate.h).

#include "tlvlink/datasets/records.h"
#include "tlvlink/sim/materials.h"
#include "tlvlink/sim/renderer.h"

namespace tlvlink::sim {

using datasets::GraspEpisode;
using datasets::GraspVariables;
using datasets::RgbImage;
using datasets::TouchSample;
using heads::kFingers;
using heads::kMoments;
using heads::Moment;

}  // namespace tlvlink::sim
