#pragma once
#ifndef TLVLINK_QUANTIZE_PIPELINE_PRIVATE
#error "calib_sources.h is internal to tools/quantize: include its public headers instead"
#endif
// Internals of calib_data.cc: listing the items of a calibration source without decoding
// images (pass 1), then reading the frames of the selected items (pass 2).

#include <cstdint>
#include <functional>
#include <string>
#include <unordered_set>
#include <vector>

#include "tlvlink/datasets/split.h"
#include "tlvlink/error.h"
#include "tlvlink/io/image.h"
#include "tlvlink/quantize/calib_data.h"

namespace tlvlink::quantize::calib_sources {

struct Item {
  std::string key;    // the loader's key (or the image's relative path)
  std::string group;  // session / object / folder: held-out never shares one with calibration
  int32_t frame = 0;  // Feel: finger * 3 + moment; else 0
  datasets::Split recorded = datasets::Split::kAll;  // the split the set records, if it does
  std::string id() const { return key + "#" + std::to_string(frame); }
};

// Pass 1 (labels / file names only), keeping the items of `split` by the datasets' one rule
// (tlvlink/datasets/detect.h): a set that records its split (written by tlvlink's simulator)
// keeps it (Touch100k: the sidecar; TAG: the train/test files; Feel: the recorded split); any
// other set is split by a hash of the group with datasets::kDefaultSplit, as tools/eval does, so
// `--calib-split train` never calibrates on the frames `tlvlink eval` tests on.
// `problems` (may be null) receives the loader's problems.
Result<std::vector<Item>> list_items(CalibFormat format, const std::string& path,
                                     datasets::Split split, datasets::ProblemEcho* problems);

// Pass 2: calls `visit` for every frame whose Item::id() is in `wanted`, in dataset order.
// `load_summary` receives the loader's problem counts. `on_item` is called per wanted frame read.
using FrameVisitor = std::function<Status(const Item& item, const tools::Image& image)>;
// `on_note` gets "skipping <why>" for an unreadable image of an image folder.
Status read_frames(CalibFormat format, const std::string& path,
                   const std::unordered_set<std::string>& wanted, const FrameVisitor& visit,
                   std::string& load_summary, const std::function<void()>& on_item,
                   const std::function<void(const std::string&)>& on_note,
                   datasets::ProblemEcho* problems);

// Image files of a folder (recursive), by extension: .jpg .jpeg .ppm .pgm .pnm .png.
bool is_image_file(const std::string& path);
Result<tools::Image> read_image(const std::string& path);

}  // namespace tlvlink::quantize::calib_sources
