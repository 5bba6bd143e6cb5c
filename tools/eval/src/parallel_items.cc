#include "parallel_items.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

namespace tlvlink::eval::internal {

Status run_items(size_t n, int32_t threads, const ItemWork& work) {
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
  const size_t helpers =
      n == 0 ? 0 : std::min<size_t>(static_cast<size_t>(std::max(threads, 1)), n) - 1;
  std::vector<std::thread> pool;
  pool.reserve(helpers);
  for (size_t t = 0; t < helpers; ++t) pool.emplace_back(loop, static_cast<int32_t>(t + 1));
  loop(0);
  for (std::thread& t : pool) t.join();
  return first;
}

}  // namespace tlvlink::eval::internal
