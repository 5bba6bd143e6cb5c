#include "tlvlink/verify/executors.h"

namespace tlvlink::verify {

ExecutorComparison compare_executors(const Model& model, const Executor& got,
                                     const Executor& want) {
  const Graph& g = model.graph();
  ExecutorComparison c;
  c.pass = true;
  for (size_t i = 0; i < g.outputs.size(); ++i) {
    c.outputs.push_back(compare_output_bytes(g, g.outputs[i], got.output(i), want.output(i)));
    c.pass = c.pass && c.outputs.back().pass;
  }
  return c;
}

}  // namespace tlvlink::verify
