// make_xnnpack_executor for builds without XNNPACK (TLVLINK_WITH_XNNPACK=OFF): a clear error
// instead of a link failure, so tools can offer `-e xnnpack` and report why it is unavailable.
#include "tlvlink/executor.h"

namespace tlvlink {

Result<std::unique_ptr<Executor>> make_xnnpack_executor(const Model& /*model*/,
                                                        const ExecutorOptions& /*options*/) {
  return Error::make(ErrorCode::kModelUnsupported,
                     "this build has no XNNPACK (TLVLINK_WITH_XNNPACK=OFF)");
}

}  // namespace tlvlink
