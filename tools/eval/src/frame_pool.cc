#include "frame_pool.h"

#include <utility>

#include "parallel_items.h"

namespace tlvlink::eval::internal {

Result<std::unique_ptr<FramePool>> FramePool::create(const Model& model,
                                                     const EmbedderOptions& options) {
  TLV_ENSURE(options.threads >= 1, ErrorCode::kInvalidArgument, "threads must be >= 1, got %d",
             options.threads);
  std::unique_ptr<FramePool> pool(new FramePool());
  EmbedderOptions one = options;
  one.threads = 1;
  for (int t = 0; t < options.threads; ++t) {
    TLV_ASSIGN_OR_RETURN(std::unique_ptr<Embedder> e, Embedder::create(model, one));
    pool->embedders_.push_back(std::move(e));
  }
  return pool;
}

FramePool::~FramePool() {
  if (running_.valid()) running_.wait();
}

Status FramePool::run(size_t n, const Work& work) { return run_items(n, workers(), work); }

void FramePool::start(size_t n, Work work) {
  if (workers() <= 1) {
    done_ = run(n, work);
    return;
  }
  running_ = std::async(std::launch::async, [this, n, w = std::move(work)] { return run(n, w); });
}

Status FramePool::wait() {
  if (!running_.valid()) return std::exchange(done_, Status{});
  return running_.get();
}

}  // namespace tlvlink::eval::internal
