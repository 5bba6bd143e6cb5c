#include "tlvlink/stream/names.h"

#include <algorithm>
#include <utility>

namespace tlvlink::stream {

OutputNames output_names(std::vector<std::string> sensors, const heads::HeadEvaluator& evaluator,
                         size_t grasp_head) {
  OutputNames n;
  n.sensors = std::move(sensors);
  for (const heads::HeadResult& r : evaluator.results()) {
    OutputNames::Head h;
    h.name = std::string(r.name);
    h.kind = heads::head_kind_name(r.kind);
    for (std::string_view l : r.labels) h.labels.emplace_back(l);
    if (r.trust != nullptr && r.trust->present) {
      const HeadTrust& t = *r.trust;
      h.accuracy = t.accuracy;
      h.majority = t.majority;
      const auto recorded = [](float v) {
        return v >= 0 ? v : std::numeric_limits<float>::quiet_NaN();
      };
      h.ci_low = recorded(t.ci_low);
      h.ci_high = recorded(t.ci_high);
      h.balanced = recorded(t.balanced_accuracy);
      h.baseline = recorded(t.baseline_accuracy);
      h.groups = static_cast<uint32_t>(std::clamp<int64_t>(t.groups, 0, UINT32_MAX));
    }
    n.heads.push_back(std::move(h));
  }
  if (grasp_head >= evaluator.grasp_head_count()) grasp_head = 0;
  n.grasp_head = std::string(evaluator.grasp_name(grasp_head));
  if (evaluator.has_grasp() && evaluator.grasp_trust(grasp_head).present) {
    n.grasp.accuracy = evaluator.grasp_trust(grasp_head).accuracy;
    n.grasp.majority = evaluator.grasp_trust(grasp_head).majority;
  }
  return n;
}

}  // namespace tlvlink::stream
