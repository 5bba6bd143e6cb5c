#pragma once
// The four evaluation tasks of TLV-Link's Table 2 and their label conventions. A class index is
// the row of a head's weight (or prompt) matrix; the canonical class names below are the ones
// tlvlink writes into a model's heads. Heads read from a model are matched to tasks by name and
// their labels to class indices by name (task_class_index), so a head with its labels in another
// order still scores correctly.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::eval {

enum class Task : uint8_t { kMaterial = 0, kHard, kRough, kGrasp };
inline constexpr std::array<Task, 4> kAllTasks = {Task::kMaterial, Task::kHard, Task::kRough,
                                                  Task::kGrasp};

// Short name used in tables and JSON: "material", "hard_soft", "rough_smooth", "grasp". It is
// also the name of the task's linear / zero-shot head in a model file.
const char* task_name(Task task);
// Column title of the table: "Material", "Hard/Soft", "Rough/Smooth", "Grasp".
const char* task_title(Task task);
// Parses a task_name(); also accepts "hard", "hardness", "rough", "roughness".
Result<Task> parse_task(std::string_view name);

// Canonical class names, index = class index = the dataset's label value (as tools/text's
// prompt sets order them):
//   material      the 20 Touch-and-Go ids 0..19 ("concrete" ... "others")
//   hard_soft     {"soft", "hard"}       class = hard (TAG's hard file: 1 hard)
//   rough_smooth  {"smooth", "rough"}    class = rough (1 rough, 0 smooth)
//   grasp         {"falling", "lifted"}  class = is_gripping
std::span<const std::string_view> task_classes(Task task);
int32_t task_class_count(Task task);

// The canonical class index a head label stands for (case-insensitive; synonyms accepted:
// grasp "true"/"success"/"gripping" = lifted, "false"/"failure"/"dropped" = falling), or an error
// naming the label and the task.
Result<int32_t> task_class_index(Task task, std::string_view label);

// The task a head name belongs to (task_name() or parse_task() synonyms), or an error.
Result<Task> task_of_head(std::string_view head_name);

}  // namespace tlvlink::eval
