#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "grasp_profile.h is internal to tools/sim: include its public headers instead"
#endif
// The contact-area model of a sensor profile (the grasp variables and the oracle use the gel of
// the sensor the episodes are rendered with).

#include "gen/contact_area.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim::internal {

GelContactModel gel_contact_model(const SensorProfile& profile);

}  // namespace tlvlink::sim::internal
