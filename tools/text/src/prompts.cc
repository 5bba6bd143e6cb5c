// The TLV-Link paper's zero-shot prompt sets (text_encoder.h). Class i of every
// set is label value i of the datasets: material = TAG id, hard/soft and rough/smooth as TAG's
// label files (1 hard, 1 rough), grasp as Feel's is_gripping (1 still held after the lift).

#include <string>
#include <vector>

#include "tlvlink/text/text_encoder.h"
#include "tlvlink/touch/materials.h"

namespace tlvlink::text {
namespace {

std::string substitute(const std::string& templ, const std::string& name) {
  std::string out;
  for (size_t i = 0; i < templ.size(); ++i) {
    if (templ.compare(i, 3, "{c}") == 0) {
      out += name;
      i += 2;
    } else {
      out += templ[i];
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> PromptSet::prompts_for(size_t class_index) const {
  if (!fixed_prompts.empty()) return {fixed_prompts.at(class_index)};
  std::vector<std::string> out;
  for (const std::string& t : templates) out.push_back(substitute(t, class_names.at(class_index)));
  return out;
}

PromptSet material_prompts() {
  PromptSet p;
  p.task = "material";
  for (const touch::MaterialClass& c : touch::material_classes()) {
    p.class_names.emplace_back(c.name);
  }
  p.templates = {"the object being touched is {c}, it is an image of {c}."};
  return p;
}

PromptSet hardness_prompts() {
  PromptSet p;
  p.task = "hard";
  p.class_names = {"soft", "hard"};
  // The paper's template, its spacing included.
  p.templates = {
      "the object being touched feels {c} , the surface show sort of {c}ness when touched."};
  return p;
}

PromptSet roughness_prompts() {
  PromptSet p;
  p.task = "rough";
  p.class_names = {"smooth", "rough"};
  p.templates = {"the object being touched feels {c}, the surface show sort of {c}ness."};
  return p;
}

PromptSet grasp_prompts() {
  PromptSet p;
  p.task = "grasp";
  p.class_names = {"falling", "lifted"};
  p.fixed_prompts = {"the object being touched is falling on the ground.",
                     "the object being touched is lifted in the air."};
  return p;
}

}  // namespace tlvlink::text
