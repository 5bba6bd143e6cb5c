#include "tlvlink/boards/board.h"

#include <dirent.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace tlvlink::boards {
namespace {

using nlohmann::json;

Result<json> read_json(const std::string& path) {
  std::ifstream in(path);
  TLV_ENSURE(in.good(), ErrorCode::kIo, "%s: cannot open", path.c_str());
  json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
  TLV_ENSURE(!j.is_discarded(), ErrorCode::kFormat, "%s: not valid JSON", path.c_str());
  return j;
}

// The configure preset `preset` in `file` or in the files it includes (relative paths).
Result<json> find_preset(const std::string& dir, const std::string& file,
                         const std::string& preset) {
  TLV_ASSIGN_OR_RETURN(const json j, read_json(dir + "/" + file));
  for (const json& p : j.value("configurePresets", json::array()))
    if (p.value("name", "") == preset) return p;
  for (const json& inc : j.value("include", json::array())) {
    auto p = find_preset(dir, inc.get<std::string>(), preset);
    if (p.ok()) return p;
  }
  return Error::make(ErrorCode::kFormat, "%s/%s: no configure preset '%s'", dir.c_str(),
                     file.c_str(), preset.c_str());
}

// Cache variables and toolchain of `p` after its parents (parents first, `p` wins).
Status merge(const std::string& dir, const std::string& file, const json& p, Board& b) {
  for (const json& parent : p.value("inherits", json::array())) {
    TLV_ASSIGN_OR_RETURN(const json pp, find_preset(dir, file, parent.get<std::string>()));
    TLV_TRY(merge(dir, file, pp, b));
  }
  const json cache = p.value("cacheVariables", json::object());
  for (const auto& [k, v] : cache.items())
    if (v.is_string()) b.cache[k] = v.get<std::string>();
  b.cross = b.cross || p.contains("toolchainFile");
  return {};
}

}  // namespace

std::string Board::option(const std::string& key) const {
  const auto it = cache.find(key);
  return it == cache.end() ? "" : it->second;
}

std::vector<std::string> board_names(const std::string& dir) {
  std::vector<std::string> out;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const std::string f = e->d_name;
      if (f.size() <= 5 || f.compare(f.size() - 5, 5, ".json") != 0) continue;
      const std::string name = f.substr(0, f.size() - 5);
      auto p = find_preset(dir, f, "board-" + name);
      if (p.ok() && p->contains("vendor") && (*p)["vendor"].contains("tlvlink/board"))
        out.push_back(name);
    }
    ::closedir(d);
  }
  std::sort(out.begin(), out.end());
  return out;
}

Result<Board> load_board(const std::string& dir, const std::string& name) {
  const std::vector<std::string> known = board_names(dir);
  if (std::find(known.begin(), known.end(), name) == known.end()) {
    std::string k;
    for (const std::string& n : known) k += (k.empty() ? "" : ", ") + n;
    return Error::make(ErrorCode::kInvalidArgument, "unknown board '%s' (%s has: %s)", name.c_str(),
                       dir.c_str(), k.empty() ? "no boards" : k.c_str());
  }
  const std::string file = name + ".json";
  TLV_ASSIGN_OR_RETURN(const json p, find_preset(dir, file, "board-" + name));
  Board b;
  b.name = name;
  b.display_name = p.value("displayName", "");
  b.description = p.value("description", "");
  TLV_TRY(merge(dir, file, p, b));
  const json& v = p["vendor"]["tlvlink/board"];
  const std::string where = dir + "/" + file + ": vendor \"tlvlink/board\"";
  for (const char* key : {"cpu", "arch", "xnnpack_kernels", "threads"})
    TLV_ENSURE(v.contains(key), ErrorCode::kFormat, "%s: no '%s'", where.c_str(), key);
  b.cpu = v.value("cpu", "");
  b.arch = v.value("arch", "");
  b.xnnpack_kernels = v.value("xnnpack_kernels", "");
  b.threads = v.value("threads", 1);
  b.cpu_affinity = v.value("cpu_affinity", "");
  b.emulated = v.value("emulated", false);
  // The CPU features the build needs: the cache variable tlvlinkd's start-up check is built with.
  std::istringstream features(b.option("TLVLINK_TARGET_FEATURES"));
  for (std::string f; features >> f;) b.cpu_features.push_back(f);
  TLV_ENSURE(b.arch == "arm64" || b.arch == "amd64", ErrorCode::kFormat,
             "%s: arch '%s' (arm64 or amd64)", where.c_str(), b.arch.c_str());
  return b;
}

}  // namespace tlvlink::boards
