#pragma once
// Umbrella header of the image component: camera frame formats, decoding, preprocessing.
#include "tlvlink/image/convert.h"
#include "tlvlink/image/decode_budget.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/image.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/pixel_format.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/image/resample.h"
