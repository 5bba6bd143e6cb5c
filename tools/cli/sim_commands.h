#pragma once
// The pieces of `tlvlink sim` (sim.cc registers them): dataset generation in the three formats,
// single frames, the extreme set, and Touch100k statistics.

#include <CLI/CLI.hpp>

#include <algorithm>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "tlvlink/io/progress.h"
#include "tlvlink/error.h"

namespace tlvlink::cli {

void add_sim_touch_commands(CLI::App& sim, int& exit_code);  // touch100k, tag
void add_sim_feel_command(CLI::App& sim, int& exit_code);
void add_sim_frame_command(CLI::App& sim, int& exit_code);
void add_sim_extreme_command(CLI::App& sim, int& exit_code);
void add_sim_scenario_command(CLI::App& sim, int& exit_code);  // needs runtime/capture
void add_sim_stats_command(CLI::App& sim, int& exit_code);
// `tlvlink sim stats DIR` and `tlvlink sim --stats DIR`.
int run_sim_stats(const std::string& dir, int top_n, bool check_files, bool json);

// Generates items [0, total) on one worker thread per generator and hands them to `consume`
// in index order, so the output does not depend on the thread count (item i depends only on
// (seed, i)). Workers fill the next batch while `consume` writes the current one.
template <typename Item, typename Generator>
Status generate_in_order(std::vector<std::unique_ptr<Generator>>& generators, int64_t total,
                         const std::function<Status(const Item&)>& consume,
                         tools::Progress& progress) {
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
      progress.add();
    }
    current = 1 - current;
  }
  return {};
}

}  // namespace tlvlink::cli
