// ImageFolder layouts with optional groups (labelled_frames.h).

#include "tlvlink/eval/labelled_frames.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <system_error>

#include "tlvlink/io/line_reader.h"

namespace tlvlink::eval {
namespace fs = std::filesystem;
namespace {

bool is_frame_name(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".ppm";
}

bool hidden(const fs::path& p) { return p.filename().string().starts_with("."); }

// The frames under one class folder, recursively, with the first folder level below the class
// (empty for a frame directly in it). A FIFO or device named like a frame is skipped and named:
// reading it could block.
struct FoundFrame {
  std::string path, relative, subfolder;
};
Status find_frames(const fs::path& class_dir, const std::string& class_name,
                   std::vector<FoundFrame>& out, std::vector<std::string>& skipped) {
  std::error_code ec;
  fs::recursive_directory_iterator it(class_dir, fs::directory_options::follow_directory_symlink,
                                      ec);
  TLV_ENSURE(!ec, ErrorCode::kIo, "%s: cannot list: %s", class_dir.c_str(), ec.message().c_str());
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    TLV_ENSURE(!ec, ErrorCode::kIo, "%s: cannot list: %s", class_dir.c_str(), ec.message().c_str());
    const fs::path& p = it->path();
    if (hidden(p)) {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (it->is_directory(ec)) continue;
    const fs::path rel = p.lexically_relative(class_dir);
    if (!is_frame_name(p)) {
      skipped.push_back(p.string() + ": not a frame (.png, .jpg, .jpeg, .ppm)");
      continue;
    }
    if (!it->is_regular_file(ec)) {
      skipped.push_back(p.string() + ": not a regular file");
      continue;
    }
    auto first = rel.begin();
    const std::string sub = std::next(first) == rel.end() ? "" : first->string();
    out.push_back({p.string(), class_name + "/" + rel.generic_string(), sub});
  }
  return {};
}

// groups.tsv: "relative<TAB>group" per line; blank lines and '#' comments skipped.
Result<std::map<std::string, std::string>> read_groups(const std::string& path) {
  std::map<std::string, std::string> groups;
  tools::LineReader reader;
  TLV_TRY(reader.open(path));
  std::string line;
  while (reader.next(line)) {
    if (line.empty() || line[0] == '#') continue;
    const size_t tab = line.find('\t');
    const bool ok = tab != std::string::npos && tab > 0 && tab + 1 < line.size() &&
                    line.find('\t', tab + 1) == std::string::npos;
    TLV_ENSURE(ok, ErrorCode::kFormat,
               "%s:%lld: expected \"<class>/<frame><TAB><group>\", got \"%.80s\"", path.c_str(),
               static_cast<long long>(reader.line_number()), line.c_str());
    const std::string key = line.substr(0, tab);
    TLV_ENSURE(groups.emplace(key, line.substr(tab + 1)).second, ErrorCode::kFormat,
               "%s:%lld: %s is listed twice", path.c_str(),
               static_cast<long long>(reader.line_number()), key.c_str());
  }
  TLV_TRY(reader.error());
  return groups;
}

}  // namespace

const char* grouping_name(Grouping g) {
  switch (g) {
    case Grouping::kGroupsFile: return "groups.tsv";
    case Grouping::kSubfolders: return "subfolders";
    case Grouping::kNone: return "none (one group per frame)";
    case Grouping::kRecordings: return "recordings";
  }
  return "?";
}

int64_t LabelledFrames::group_count() const {
  std::set<std::string> g;
  for (const LabelledFrame& f : frames) g.insert(f.group);
  return static_cast<int64_t>(g.size());
}

Result<LabelledFrames> read_labelled_folder(const std::string& dir) {
  std::error_code ec;
  TLV_ENSURE(fs::is_directory(dir, ec), ErrorCode::kIo,
             "%s: not a folder (expected <class>/<frame> inside)", dir.c_str());
  LabelledFrames set;
  set.dir = dir;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (!hidden(e.path()) && e.is_directory(ec)) set.classes.push_back(e.path().filename());
  }
  std::sort(set.classes.begin(), set.classes.end());
  TLV_ENSURE(set.classes.size() >= 2, ErrorCode::kFormat,
             "%s: %zu class folder(s); a head needs at least two (%s/<class>/<frame>)", dir.c_str(),
             set.classes.size(), dir.c_str());

  std::vector<std::vector<FoundFrame>> found(set.classes.size());
  bool any_subfolder = false, all_subfolders = true;
  for (size_t c = 0; c < set.classes.size(); ++c) {
    TLV_TRY(find_frames(fs::path(dir) / set.classes[c], set.classes[c], found[c], set.skipped));
    TLV_ENSURE(!found[c].empty(), ErrorCode::kFormat, "%s/%s: no frames (.png, .jpg, .jpeg, .ppm)",
               dir.c_str(), set.classes[c].c_str());
    std::sort(found[c].begin(), found[c].end(),
              [](const FoundFrame& a, const FoundFrame& b) { return a.path < b.path; });
    for (const FoundFrame& f : found[c]) {
      any_subfolder |= !f.subfolder.empty();
      all_subfolders &= !f.subfolder.empty();
    }
  }

  const std::string groups_path = (fs::path(dir) / "groups.tsv").string();
  std::map<std::string, std::string> listed;
  if (fs::exists(groups_path, ec)) {
    auto read = read_groups(groups_path);
    if (!read.ok()) return read.error();
    listed = std::move(read).value();
    set.grouping = Grouping::kGroupsFile;
  } else if (any_subfolder) {
    TLV_ENSURE(all_subfolders, ErrorCode::kFormat,
               "%s: some frames are in group subfolders and some are not; put every frame in "
               "<class>/<group>/ or list the groups in %s",
               dir.c_str(), groups_path.c_str());
    set.grouping = Grouping::kSubfolders;
  }

  std::set<std::string> used;
  for (size_t c = 0; c < set.classes.size(); ++c) {
    for (FoundFrame& f : found[c]) {
      std::string group;
      switch (set.grouping) {
        case Grouping::kGroupsFile: {
          auto it = listed.find(f.relative);
          TLV_ENSURE(it != listed.end(), ErrorCode::kFormat, "%s: %s is not listed in %s",
                     dir.c_str(), f.relative.c_str(), groups_path.c_str());
          group = it->second;
          used.insert(f.relative);
          break;
        }
        case Grouping::kSubfolders: group = set.classes[c] + "/" + f.subfolder; break;
        case Grouping::kNone:
        case Grouping::kRecordings: group = f.relative; break;
      }
      set.frames.push_back(
          {std::move(f.path), std::move(f.relative), static_cast<int32_t>(c), std::move(group)});
    }
  }
  for (const auto& [key, group] : listed) {
    TLV_ENSURE(used.count(key) != 0, ErrorCode::kFormat,
               "%s: lists %s, which is not a frame under %s/<class>/", groups_path.c_str(),
               key.c_str(), dir.c_str());
  }
  return set;
}

}  // namespace tlvlink::eval
