#pragma once
// Umbrella header for the on-device runtime's public API.
#include "tlvlink/error.h"
#include "tlvlink/executor.h"
#include "tlvlink/graph.h"
#include "tlvlink/metadata.h"
#include "tlvlink/model.h"
#include "tlvlink/quant_math.h"
