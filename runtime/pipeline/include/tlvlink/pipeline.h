#pragma once
// Umbrella header of the pipeline component: contact gating, smoothing, grasps, presses, the
// per-frame chain and its records.
#include "tlvlink/pipeline/contact_gate.h"
#include "tlvlink/pipeline/frame_processor.h"
#include "tlvlink/pipeline/grasp_tracker.h"
#include "tlvlink/pipeline/latency_stats.h"
#include "tlvlink/pipeline/predictions.h"
#include "tlvlink/pipeline/press_tracker.h"
#include "tlvlink/pipeline/smoother.h"
