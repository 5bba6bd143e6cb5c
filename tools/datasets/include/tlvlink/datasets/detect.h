#pragma once
// The one rule for what a dataset path holds and which split its items follow, used by
// `tlvlink eval` / `heads fit`, `tlvlink quantize` and the trainer.
//
// Format, by the files each format's loader reads (never guessed from images):
//   DIR/data_list.json                               Touch100k
//   DIR/train.txt or DIR/test.txt                    Touch-and-Go (label files)
//   DIR/train_info.json or DIR/test_info.json        Feel, TLV-Link's repacked layout
//   DIR/calandra_corl2017_*.h5, or one such .h5 file Feel HDF5
// A directory holding the markers of two formats is ambiguous: an error naming both (pass the
// format explicitly). A directory holding none is not a dataset.
//
// Split: a set written by tlvlink's simulator (it holds tlvlink_sim.json; a Touch100k set also
// needs its sidecar, the only place that format records a split) keeps its recorded split. Any
// other set is split by a hash of the session (touch) or object (grasp) with kDefaultSplit, so
// `quantize --calib-split train` never calibrates on the frames `eval` tests on, and the trainer
// never trains on them.
//
//   TLV_ASSIGN_OR_RETURN(DatasetFormat f, detect_dataset_format(dir));
//   std::optional<HashSplit> hash = split_to_apply(dir, f, forced_resplit);  // nullopt: recorded

#include <cstdint>
#include <optional>
#include <string>

#include "tlvlink/datasets/split.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets {

enum class DatasetFormat : uint8_t { kTouch100k, kTouchAndGo, kFeelHdf5, kFeelRepacked };
// "touch100k", "tag", "feel", "feel-repacked" (the names `--calib-format` takes).
const char* dataset_format_name(DatasetFormat format);
bool is_touch_format(DatasetFormat format);  // Touch100k, Touch-and-Go

// What tlvlink's simulator writes beside every set it generates.
inline constexpr const char* kGeneratorRecord = "tlvlink_sim.json";
// The published Feel files: calandra_corl2017_NNN.h5.
inline constexpr const char* kFeelFilePrefix = "calandra_corl2017_";
// The hash split of a set that records none: 20 % of sessions / objects, seed 0.
inline constexpr HashSplit kDefaultSplit{0.2, 0};

// The format `path` holds by its marker files; nullopt when it holds none. Errors: `path` does
// not exist, or is a file other than a Feel .h5 file (kIo); markers of two formats (kFormat).
Result<std::optional<DatasetFormat>> probe_dataset_format(const std::string& path);
// probe_dataset_format, with "no marker" an error (kFormat) naming the markers looked for.
Result<DatasetFormat> detect_dataset_format(const std::string& path);

// The directory of a dataset: `path` itself, or the directory holding a Feel .h5 file.
std::string dataset_dir(const std::string& path);
// True when the set records tlvlink's simulator as its maker (kGeneratorRecord beside it).
bool is_generated(const std::string& path);
// True when the set's items carry a recorded train/test split (see the rule above).
bool records_split(const std::string& path, DatasetFormat format);
// The hash split to apply to the set: `forced` when given, else none (nullopt: use the recorded
// split) when records_split(), else `fallback`.
std::optional<HashSplit> split_to_apply(const std::string& path, DatasetFormat format,
                                        const std::optional<HashSplit>& forced,
                                        const HashSplit& fallback = kDefaultSplit);

}  // namespace tlvlink::datasets
