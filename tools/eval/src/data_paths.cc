#include "data_paths.h"

#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/sim/sensor.h"

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
  if (requested != TouchFormat::kAuto) {
    TLV_ENSURE(dir_exists(dir), ErrorCode::kIo, "touch dataset '%s' is not a directory",
               dir.c_str());
    return requested;
  }
  TLV_ASSIGN_OR_RETURN(const datasets::DatasetFormat f, datasets::detect_dataset_format(dir));
  TLV_ENSURE(datasets::is_touch_format(f), ErrorCode::kFormat,
             "%s: a %s set, not a touch dataset (Touch100k or Touch-and-Go)", dir.c_str(),
             datasets::dataset_format_name(f));
  return f == datasets::DatasetFormat::kTouch100k ? TouchFormat::kTouch100k
                                                  : TouchFormat::kTouchAndGo;
}

Result<GraspFormat> detect_grasp_format(const std::string& path, GraspFormat requested) {
  if (requested != GraspFormat::kAuto) {
    TLV_ENSURE(file_exists(path) || dir_exists(path), ErrorCode::kIo,
               "grasp dataset '%s' is neither a file nor a directory", path.c_str());
    return requested;
  }
  TLV_ASSIGN_OR_RETURN(const datasets::DatasetFormat f, datasets::detect_dataset_format(path));
  TLV_ENSURE(!datasets::is_touch_format(f), ErrorCode::kFormat,
             "%s: a %s set, not a grasp dataset (Feel HDF5 or repacked)", path.c_str(),
             datasets::dataset_format_name(f));
  return f == datasets::DatasetFormat::kFeelHdf5 ? GraspFormat::kFeelHdf5
                                                 : GraspFormat::kFeelRepacked;
}

datasets::DatasetFormat dataset_format(TouchFormat format) {
  return format == TouchFormat::kTouchAndGo ? datasets::DatasetFormat::kTouchAndGo
                                            : datasets::DatasetFormat::kTouch100k;
}

datasets::DatasetFormat dataset_format(GraspFormat format) {
  return format == GraspFormat::kFeelRepacked ? datasets::DatasetFormat::kFeelRepacked
                                              : datasets::DatasetFormat::kFeelHdf5;
}

// The generator record is a few KB; a larger one is not ours (read bounded, regular files only).
constexpr size_t kMaxGeneratorRecordBytes = size_t{1} << 20;

static std::optional<std::string> read_generator_record(const std::string& path) {
  auto bytes = tools::read_file(join(datasets::dataset_dir(path), datasets::kGeneratorRecord),
                                kMaxGeneratorRecordBytes);
  if (!bytes.ok()) return std::nullopt;
  return std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size());
}

std::optional<std::string> generator_json(const std::string& path) {
  const std::optional<std::string> text = read_generator_record(path);
  if (!text) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object() || !j.contains("generator")) return std::nullopt;
  return j.at("generator").dump();
}

std::optional<datasets::HashSplit> split_to_apply(const EvalData& data, const std::string& path,
                                                  datasets::DatasetFormat format) {
  return datasets::split_to_apply(path, format, data.resplit, data.default_split);
}

std::string split_source(const std::optional<datasets::HashSplit>& split) {
  if (!split) return "recorded";
  char buf[96];
  std::snprintf(buf, sizeof buf, "hash(test_fraction=%g, seed=%llu)", split->test_fraction,
                static_cast<unsigned long long>(split->seed));
  return buf;
}

// Non-blank lines, for the progress total. Read in chunks, never a line at a time: an index
// with a 1.5 GB line must not cost 1.5 GB here before the loader skips that line.
int64_t count_lines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  int64_t n = 0;
  bool blank = true;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      const char c = chunk[i];
      if (c == '\n') {
        n += blank ? 0 : 1;
        blank = true;
      } else if (c != ' ' && c != '\t' && c != '\r') {
        blank = false;
      }
    }
  }
  return n + (blank ? 0 : 1);
}

int64_t expected_touch_items(const std::string& dir, TouchFormat format) {
  if (format == TouchFormat::kTouch100k) return count_lines(join(dir, datasets::kTouch100kIndex));
  return count_lines(join(dir, "train.txt")) + count_lines(join(dir, "test.txt"));
}

int64_t expected_grasp_items(const std::string& path, GraspFormat format) {
  if (format == GraspFormat::kFeelRepacked)
    return count_lines(join(path, "train_info.json")) + count_lines(join(path, "test_info.json"));
  const std::optional<std::string> text = read_generator_record(path);
  if (!text || file_exists(path)) return 0;  // one .h5 file of a set: its share is unknown
  const nlohmann::json j = nlohmann::json::parse(*text, nullptr, false);
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

Result<datasets::RgbImage> jpeg_path(const datasets::RgbImage& frame, int32_t quality) {
  const image::Image in{frame.width, frame.height, 3, frame.rgb};
  TLV_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, image::encode_jpeg(in, quality));
  TLV_ASSIGN_OR_RETURN(image::Image out, image::decode_jpeg(bytes, "JPEG path"));
  return datasets::RgbImage{out.height, out.width, std::move(out.pixels)};
}

Status LivePaths::apply(const std::string& sensor, std::span<uint8_t> rgb) {
  std::unique_ptr<sim::LivePath>& path = paths_[sensor];
  if (!path) {
    TLV_ASSIGN_OR_RETURN(const sim::SensorProfile profile, sim::sensor_profile(sensor));
    TLV_ASSIGN_OR_RETURN(path, sim::LivePath::create(profile));
  }
  return path->apply(rgb);
}

}  // namespace tlvlink::eval::internal
