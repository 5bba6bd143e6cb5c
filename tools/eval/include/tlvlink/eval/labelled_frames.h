#pragma once
// A user's labelled frames, for heads of their own: image files in the ImageFolder convention,
// or camera recordings (`.tlvraw`, what `tlvlink record --device` and tlvlinkd's recorder write)
// named in a labels file. First, image files:
//
//   DIR/<class>/<frame>.png|jpg|jpeg|ppm        classes are the folder names, sorted
//   DIR/groups.tsv                              optional: "<class>/<frame><TAB><group>" per line
//
// A group is the object or session a frame shows: validation keeps a group's frames together,
// so no head is scored on an object it was fitted on. Groups come from groups.tsv when present,
// else from one folder level below the class (DIR/<class>/<group>/<frame>), else each frame is
// its own group and `grouping` says that the scores are then optimistic.
//
//   auto set = eval::read_labelled_folder("frames/");
//   // set->classes = {"rough", "smooth"}, set->frames[i].path / label / group
//
// Recordings: a labels file, one recording per line (paths relative to the file; '#' comments):
//
//   <recording.tlvraw><TAB><class>[<TAB><from_s><TAB><to_s>][<TAB><group>]
//
// from/to select the frames whose capture time (seconds from the recording's start) lies in
// [from, to); "-" or absent: all. The group defaults to the recording (a session). Frames that
// repeat the previous one (a held frame) are left out; `stride` keeps every stride-th frame.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::eval {

struct LabelledFrame {
  std::string path;      // as found under the folder (DIR/<class>/...), or the recording
  std::string relative;  // <class>/... (the key of groups.tsv)
  int32_t label = 0;     // index into LabelledFrames::classes
  std::string group;
  uint64_t record_offset = 0;  // > 0: the frame is this record of the recording `path`
};

enum class Grouping : uint8_t {
  kGroupsFile = 0,  // DIR/groups.tsv
  kSubfolders,      // DIR/<class>/<group>/<frame>
  kNone,            // every frame its own group
  kRecordings,      // the labels file: each recording (or its group column)
};
const char* grouping_name(Grouping g);  // "groups.tsv", "subfolders", "none (one group per frame)"

struct LabelledFrames {
  std::string dir;
  std::vector<std::string> classes;
  std::vector<LabelledFrame> frames;  // sorted by class, then path
  Grouping grouping = Grouping::kNone;
  std::vector<std::string> skipped;  // files that are not frames, each "path: why"
  int64_t group_count() const;
};

// Frame files: .png, .jpg, .jpeg, .ppm (any case). Errors, each naming the path (and line):
// DIR missing or not a folder, fewer than two class folders, a class folder without frames,
// a groups.tsv line that is not "path<TAB>group", names a file that is not a frame of DIR, or
// lists a frame twice, and a frame groups.tsv does not list.
Result<LabelledFrames> read_labelled_folder(const std::string& dir);

// Errors, naming the file and line: a malformed line, an unreadable or damaged recording, a
// time range with no frame, fewer than two classes. `dir` of the result is the labels file.
Result<LabelledFrames> read_labelled_recordings(const std::string& labels_file, int32_t stride = 1);

}  // namespace tlvlink::eval
