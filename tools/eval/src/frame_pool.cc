#include "frame_pool.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

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

Status FramePool::run(size_t n, const Work& work) {
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex m;
  size_t first_item = n;
  Status first;
  auto loop = [&](int32_t worker) {
    for (size_t i; !failed.load() && (i = next.fetch_add(1)) < n;) {
      if (Status st = work(i, worker); !st.ok()) {
        failed = true;
        const std::lock_guard<std::mutex> lock(m);
        if (i < first_item) {
          first_item = i;
          first = std::move(st);
        }
      }
    }
  };
  const size_t helpers = n == 0 ? 0 : std::min<size_t>(embedders_.size(), n) - 1;
  std::vector<std::thread> threads;
  threads.reserve(helpers);
  for (size_t t = 0; t < helpers; ++t) threads.emplace_back(loop, static_cast<int32_t>(t + 1));
  loop(0);
  for (std::thread& t : threads) t.join();
  return first;
}

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
