// Task names and label conventions (tasks.h).

#include "tlvlink/eval/tasks.h"

#include <cctype>
#include <string>

namespace tlvlink::eval {
namespace {

constexpr std::string_view kMaterialClasses[] = {
    "concrete",         "plastic",        "glass",  "wood",  "metal", "brick", "tile", "leather",
    "synthetic fabric", "natural fabric", "rubber", "paper", "tree",  "grass", "soil", "rock",
    "gravel",           "sand",           "plants", "others"};
constexpr std::string_view kHardClasses[] = {"soft", "hard"};
constexpr std::string_view kRoughClasses[] = {"smooth", "rough"};
constexpr std::string_view kGraspClasses[] = {"falling", "lifted"};

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool any_of(const std::string& s, std::initializer_list<std::string_view> names) {
  for (std::string_view n : names)
    if (s == n) return true;
  return false;
}

}  // namespace

const char* task_name(Task task) {
  switch (task) {
    case Task::kMaterial: return "material";
    case Task::kHard: return "hard_soft";
    case Task::kRough: return "rough_smooth";
    case Task::kGrasp: return "grasp";
  }
  return "?";
}

const char* task_title(Task task) {
  switch (task) {
    case Task::kMaterial: return "Material";
    case Task::kHard: return "Hard/Soft";
    case Task::kRough: return "Rough/Smooth";
    case Task::kGrasp: return "Grasp";
  }
  return "?";
}

Result<Task> parse_task(std::string_view name) {
  const std::string s = lower(name);
  if (any_of(s, {"material", "materials"})) return Task::kMaterial;
  if (any_of(s, {"hard_soft", "hard", "hardness", "hard/soft"})) return Task::kHard;
  if (any_of(s, {"rough_smooth", "rough", "roughness", "rough/smooth"})) return Task::kRough;
  if (any_of(s, {"grasp", "grasping"})) return Task::kGrasp;
  return Error::make(ErrorCode::kInvalidArgument,
                     "unknown task '%.*s' (material, hard_soft, rough_smooth, grasp)",
                     static_cast<int>(name.size()), name.data());
}

Result<Task> task_of_head(std::string_view head_name) { return parse_task(head_name); }

std::span<const std::string_view> task_classes(Task task) {
  switch (task) {
    case Task::kMaterial: return kMaterialClasses;
    case Task::kHard: return kHardClasses;
    case Task::kRough: return kRoughClasses;
    case Task::kGrasp: return kGraspClasses;
  }
  return {};
}

int32_t task_class_count(Task task) { return static_cast<int32_t>(task_classes(task).size()); }

Result<int32_t> task_class_index(Task task, std::string_view label) {
  const std::string s = lower(label);
  const std::span<const std::string_view> classes = task_classes(task);
  for (size_t i = 0; i < classes.size(); ++i)
    if (s == classes[i]) return static_cast<int32_t>(i);
  if (task == Task::kGrasp) {
    if (any_of(s, {"true", "success", "gripping", "held", "1"})) return 1;
    if (any_of(s, {"false", "failure", "dropped", "slipped", "0"})) return 0;
  }
  return Error::make(ErrorCode::kModelInvalidMetadata, "head label '%.*s' is not a %s class",
                     static_cast<int>(label.size()), label.data(), task_name(task));
}

}  // namespace tlvlink::eval
