#pragma once
// `tlvlink strip MODEL --scene S -o OUT`: the model with only what the scene uses — its
// per-frame heads (linear probes, zero-shot heads with their label tables and prompt matrices),
// the grasp head when the scene predicts grasps, and `golden_pairs` of the golden pairs. The
// graph and every constant are kept (model_copy.h), so the copy computes bit-identical
// embeddings; the remaining golden pairs still hold (they are checked, with the scene's
// sensors and heads, by daemon::check_model on the written file).

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/daemon/scene.h"
#include "tlvlink/error.h"

namespace tlvlink::boards {

struct StripReport {
  std::vector<std::string> kept, removed;  // heads, as "kind:name"
  size_t golden_before = 0, golden_after = 0;
  uint64_t bytes_before = 0, bytes_after = 0;
  bool golden_pass = false;
  std::string source_key_id;  // hex key id when the source model was signed, else ""
  bool signed_copy = false;   // the copy was signed with secret_key_file
};

// The copy is unsigned (a changed file needs a new signature) unless `secret_key_file` names a
// key (`tlvlink keygen`): it is then signed with it, so a daemon with `model_public_key` accepts
// it. A signed source with no key given is reported (source_key_id) so the caller can warn.
// Errors (out_path keeps what it held before): the model does not load; the scene names a head the
// model lacks (listing the model's heads) or predicts grasps with a model without a grasp head;
// a sensor of the scene whose frames cannot feed the model's input (naming the sensor); the
// golden pairs of the written copy do not hold.
Result<StripReport> strip_model(const std::string& model_path, const daemon::Scene& scene,
                                const std::string& out_path,
                                const std::string& secret_key_file = "");

}  // namespace tlvlink::boards
