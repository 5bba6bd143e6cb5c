#pragma once
// Umbrella header of the verify component: golden pairs and the output comparison rule.
#include "tlvlink/verify/compare.h"
#include "tlvlink/verify/golden.h"
