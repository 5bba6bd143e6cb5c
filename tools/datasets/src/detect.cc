// Dataset format detection and the split rule (detect.h).

#include "tlvlink/datasets/detect.h"

#include <filesystem>
#include <string>
#include <vector>

#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"

namespace tlvlink::datasets {
namespace {

namespace fs = std::filesystem;

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

bool is_feel_file_name(const fs::path& p) {
  return p.filename().string().rfind(kFeelFilePrefix, 0) == 0 && p.extension() == ".h5";
}

bool has_feel_files(const fs::path& dir) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (is_feel_file_name(e.path()) && is_file(e.path())) return true;
  return false;
}

// "data_list.json (Touch100k)" for error messages.
std::string marker_text(DatasetFormat f) {
  const TagLayout tag;
  switch (f) {
    case DatasetFormat::kTouch100k: return std::string(kTouch100kIndex) + " (Touch100k)";
    case DatasetFormat::kTouchAndGo:
      return tag.material_train + " / " + tag.material_test + " (Touch-and-Go)";
    case DatasetFormat::kFeelRepacked: return "train_info.json / test_info.json (Feel repacked)";
    case DatasetFormat::kFeelHdf5: return std::string(kFeelFilePrefix) + "*.h5 (Feel HDF5)";
  }
  return "?";
}

}  // namespace

const char* dataset_format_name(DatasetFormat format) {
  switch (format) {
    case DatasetFormat::kTouch100k: return "touch100k";
    case DatasetFormat::kTouchAndGo: return "tag";
    case DatasetFormat::kFeelHdf5: return "feel";
    case DatasetFormat::kFeelRepacked: return "feel-repacked";
  }
  return "?";
}

bool is_touch_format(DatasetFormat f) {
  return f == DatasetFormat::kTouch100k || f == DatasetFormat::kTouchAndGo;
}

Result<std::optional<DatasetFormat>> probe_dataset_format(const std::string& path) {
  const fs::path p(path);
  std::error_code ec;
  TLV_ENSURE(fs::exists(p, ec), ErrorCode::kIo, "dataset '%s' does not exist", path.c_str());
  if (!fs::is_directory(p, ec)) {
    TLV_ENSURE(is_file(p) && p.extension() == ".h5", ErrorCode::kIo,
               "dataset '%s' is neither a directory nor a Feel .h5 file", path.c_str());
    return std::optional<DatasetFormat>(DatasetFormat::kFeelHdf5);
  }
  const TagLayout tag;
  std::vector<DatasetFormat> found;
  if (is_file(p / kTouch100kIndex)) found.push_back(DatasetFormat::kTouch100k);
  if (is_file(p / tag.material_train) || is_file(p / tag.material_test))
    found.push_back(DatasetFormat::kTouchAndGo);
  if (is_file(p / "train_info.json") || is_file(p / "test_info.json"))
    found.push_back(DatasetFormat::kFeelRepacked);
  if (has_feel_files(p)) found.push_back(DatasetFormat::kFeelHdf5);
  if (found.empty()) return std::optional<DatasetFormat>();
  TLV_ENSURE(found.size() == 1, ErrorCode::kFormat,
             "%s: ambiguous dataset, it holds both %s and %s; name the format", path.c_str(),
             marker_text(found[0]).c_str(), marker_text(found[1]).c_str());
  return std::optional<DatasetFormat>(found[0]);
}

Result<DatasetFormat> detect_dataset_format(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(const std::optional<DatasetFormat> format, probe_dataset_format(path));
  TLV_ENSURE(format.has_value(), ErrorCode::kFormat,
             "cannot tell the format of '%s': no %s, %s, %s or %s", path.c_str(),
             marker_text(DatasetFormat::kTouch100k).c_str(),
             marker_text(DatasetFormat::kTouchAndGo).c_str(),
             marker_text(DatasetFormat::kFeelRepacked).c_str(),
             marker_text(DatasetFormat::kFeelHdf5).c_str());
  return *format;
}

std::string dataset_dir(const std::string& path) {
  if (!is_file(path)) return path;
  const fs::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

bool is_generated(const std::string& path) {
  return is_file(fs::path(dataset_dir(path)) / kGeneratorRecord);
}

bool records_split(const std::string& path, DatasetFormat format) {
  if (!is_generated(path)) return false;
  // Touch100k records a split only in the simulator's sidecar (a set written with
  // --no-sidecar has none).
  return format != DatasetFormat::kTouch100k ||
         is_file(fs::path(dataset_dir(path)) / kTouch100kSidecar);
}

std::optional<HashSplit> split_to_apply(const std::string& path, DatasetFormat format,
                                        const std::optional<HashSplit>& forced,
                                        const HashSplit& fallback) {
  if (forced) return forced;
  if (records_split(path, format)) return std::nullopt;
  return fallback;
}

}  // namespace tlvlink::datasets
