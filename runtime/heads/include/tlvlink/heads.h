#pragma once
// Umbrella header of the heads component: a model's heads on its embeddings.
#include "tlvlink/head_trust.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/heads/grasp_difference.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/heads/head_math.h"
