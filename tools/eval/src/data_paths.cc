#include "data_paths.h"

#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "tlvlink/datasets/touch100k.h"

namespace tlvlink::eval::internal {

bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool dir_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string join(const std::string& dir, const std::string& name) {
  return dir.empty() || dir.back() == '/' ? dir + name : dir + "/" + name;
}

Result<TouchFormat> detect_touch_format(const std::string& dir, TouchFormat requested) {
  TLV_ENSURE(dir_exists(dir), ErrorCode::kIo, "touch dataset '%s' is not a directory",
             dir.c_str());
  if (requested != TouchFormat::kAuto) return requested;
  if (file_exists(join(dir, datasets::kTouch100kIndex))) return TouchFormat::kTouch100k;
  if (file_exists(join(dir, "train.txt")) || file_exists(join(dir, "test.txt")))
    return TouchFormat::kTouchAndGo;
  return Error::make(ErrorCode::kFormat,
                     "%s: neither a Touch100k set (data_list.json) nor a Touch-and-Go set "
                     "(train.txt / test.txt label files)",
                     dir.c_str());
}

Result<GraspFormat> detect_grasp_format(const std::string& path, GraspFormat requested) {
  const bool is_file = file_exists(path);
  TLV_ENSURE(is_file || dir_exists(path), ErrorCode::kIo,
             "grasp dataset '%s' is neither a file nor a directory", path.c_str());
  if (requested != GraspFormat::kAuto) return requested;
  if (is_file) return GraspFormat::kFeelHdf5;
  if (file_exists(join(path, "train_info.json")) || file_exists(join(path, "test_info.json")))
    return GraspFormat::kFeelRepacked;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(path, ec)) {
    if (e.path().extension() == ".h5") return GraspFormat::kFeelHdf5;
  }
  return Error::make(ErrorCode::kFormat,
                     "%s: neither a Feel HDF5 set (*.h5) nor TLV-Link's repacked layout "
                     "(train_info.json / test_info.json)",
                     path.c_str());
}

std::string dataset_dir(const std::string& path) {
  if (!file_exists(path)) return path;
  const std::filesystem::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

bool is_generated(const std::string& path) {
  return file_exists(join(dataset_dir(path), kSimRecord));
}

std::optional<std::string> generator_json(const std::string& path) {
  std::ifstream in(join(dataset_dir(path), kSimRecord));
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object() || !j.contains("generator")) return std::nullopt;
  return j.at("generator").dump();
}

std::optional<datasets::HashSplit> split_to_apply(const EvalData& data, bool generated) {
  if (data.resplit) return data.resplit;
  if (generated) return std::nullopt;
  return data.default_split;
}

std::string split_source(const std::optional<datasets::HashSplit>& split) {
  if (!split) return "recorded";
  char buf[96];
  std::snprintf(buf, sizeof buf, "hash(test_fraction=%g, seed=%llu)", split->test_fraction,
                static_cast<unsigned long long>(split->seed));
  return buf;
}

int64_t count_lines(const std::string& path) {
  std::ifstream in(path);
  int64_t n = 0;
  std::string line;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) ++n;
  return n;
}

int64_t expected_touch_items(const std::string& dir, TouchFormat format) {
  if (format == TouchFormat::kTouch100k) return count_lines(join(dir, datasets::kTouch100kIndex));
  return count_lines(join(dir, "train.txt")) + count_lines(join(dir, "test.txt"));
}

int64_t expected_grasp_items(const std::string& path, GraspFormat format) {
  if (format == GraspFormat::kFeelRepacked)
    return count_lines(join(path, "train_info.json")) + count_lines(join(path, "test_info.json"));
  std::ifstream in(join(dataset_dir(path), kSimRecord));
  if (!in || file_exists(path)) return 0;  // one .h5 file of a set: its share is unknown
  std::stringstream ss;
  ss << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, false);
  if (j.is_discarded() || !j.contains("counts") || !j["counts"].contains("items")) return 0;
  const nlohmann::json& items = j["counts"]["items"];
  return items.is_number_integer() ? items.get<int64_t>() : 0;
}

void fill_split_counts(SplitInfo& info, const std::vector<std::string>& groups,
                       const std::vector<uint8_t>& is_test) {
  std::set<std::string> train, test;
  info.train_items = info.test_items = 0;
  for (size_t i = 0; i < groups.size(); ++i) {
    if (is_test[i] != 0) {
      ++info.test_items;
      test.insert(groups[i]);
    } else {
      ++info.train_items;
      train.insert(groups[i]);
    }
  }
  info.train_groups = static_cast<int64_t>(train.size());
  info.test_groups = static_cast<int64_t>(test.size());
}

}  // namespace tlvlink::eval::internal
