#pragma once
// The threaded batch generator of the simulator's datasets: items [0, total) made by one worker
// thread per generator and handed to `consume` in index order, so the output does not depend on
// the thread count (item i depends only on (seed, i)). Workers fill the next batch (4 items per
// worker) while `consume` takes the current one. Works with any generator that has
// `Status generate(int64_t index, Item& out)` (TouchSampleGenerator, GraspEpisodeGenerator).
//
//   std::vector<std::unique_ptr<TouchSampleGenerator>> gens = ...;  // one per thread
//   TLV_TRY(generate_in_order<TouchSample>(gens, gens[0]->size(),
//                                          [&](const TouchSample& s) { return writer.write(s); }));

#include <algorithm>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <thread>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::sim {

// The first error of a worker or of `consume` stops the run and is returned (a batch being
// filled is waited for before the buffers go). `on_consumed` is called after each item consumed.
template <typename Item, typename Generator>
Status generate_in_order(std::vector<std::unique_ptr<Generator>>& generators, int64_t total,
                         const std::function<Status(const Item&)>& consume,
                         const std::function<void()>& on_consumed = {}) {
  TLV_ENSURE(!generators.empty(), ErrorCode::kInvalidArgument, "no generator");
  const auto workers = static_cast<int64_t>(generators.size());
  const int64_t batch = workers * 4;
  std::vector<Item> buffers[2] = {std::vector<Item>(static_cast<size_t>(batch)),
                                  std::vector<Item>(static_cast<size_t>(batch))};
  auto fill = [&generators, workers, batch, total](std::vector<Item>& buf, int64_t start) {
    return std::async(std::launch::async, [&generators, &buf, workers, batch, total, start] {
      const int64_t n = std::min(batch, total - start);
      std::vector<Status> status(static_cast<size_t>(workers));
      std::vector<std::thread> threads;
      for (int64_t w = 0; w < workers; ++w) {
        threads.emplace_back([&, w] {
          for (int64_t k = w; k < n; k += workers) {
            Status s = generators[static_cast<size_t>(w)]->generate(start + k,
                                                                    buf[static_cast<size_t>(k)]);
            if (!s.ok()) {
              status[static_cast<size_t>(w)] = s;
              return;
            }
          }
        });
      }
      for (auto& t : threads) t.join();
      for (const Status& s : status)
        if (!s.ok()) return s;
      return Status();
    });
  };
  size_t current = 0;
  std::future<Status> pending = fill(buffers[0], 0);
  for (int64_t start = 0; start < total; start += batch) {
    TLV_TRY(pending.get());
    const int64_t next = start + batch;
    // (An early return below waits for this batch in ~future before the buffers go.)
    if (next < total) pending = fill(buffers[1 - current], next);
    const int64_t n = std::min(batch, total - start);
    for (int64_t k = 0; k < n; ++k) {
      TLV_TRY(consume(buffers[current][static_cast<size_t>(k)]));
      if (on_consumed) on_consumed();
    }
    current = 1 - current;
  }
  return {};
}

}  // namespace tlvlink::sim
