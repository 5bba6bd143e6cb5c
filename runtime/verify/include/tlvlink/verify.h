#pragma once
// Umbrella header of the verify component: golden pairs and the output comparison rule
// (between a run and its expectation, or between two executors).
#include "tlvlink/verify/compare.h"
#include "tlvlink/verify/executors.h"
#include "tlvlink/verify/golden.h"
#include "tlvlink/verify/golden_heads.h"
