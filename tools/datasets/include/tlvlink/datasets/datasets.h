#pragma once
// tlvlink_datasets: writers and streaming loaders for the Touch100k, Touch-and-Go and Feel
// formats, and Touch100k language statistics. See tools/datasets/README.md.

#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/feel.h"
#include "tlvlink/datasets/loader.h"
#include "tlvlink/datasets/report.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/datasets/stats.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "tlvlink/datasets/writer.h"
