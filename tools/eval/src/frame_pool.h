#pragma once
#ifndef TLVLINK_EVAL_PRIVATE
#error "frame_pool.h is internal to tools/eval: include its public headers instead"
#endif
// The embedding work of eval and heads fit on N threads, one frame per thread at a time. One
// frame's layers on N XNNPACK threads kept little more than one core busy (decoding,
// preprocessing, re-encodings and the difference statistics run on one); N frames at once, each
// on one XNNPACK thread, keep N. Results are placed by item, so they are the same for any N.

#include <cstddef>
#include <functional>
#include <future>
#include <memory>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"

namespace tlvlink::eval::internal {

class FramePool {
 public:
  // options.threads workers, each with its own Embedder (an executor on one thread); 1: every
  // item runs on the caller's thread.
  static Result<std::unique_ptr<FramePool>> create(const Model& model,
                                                   const EmbedderOptions& options);
  ~FramePool();  // waits for a batch still running

  int32_t workers() const { return static_cast<int32_t>(embedders_.size()); }
  Embedder& embedder(int32_t worker) { return *embedders_[static_cast<size_t>(worker)]; }

  using Work = std::function<Status(size_t item, int32_t worker)>;
  // work(i, w) for every i in [0, n), w the worker running it; items are taken in order, and
  // after a failure no further one is started. Returns the failure of the lowest item.
  Status run(size_t n, const Work& work);
  // run() in the background (on the caller's thread when there is one worker), so that the
  // caller can load the next batch meanwhile; wait() returns its status. One batch at a time.
  void start(size_t n, Work work);
  Status wait();

 private:
  FramePool() = default;
  std::vector<std::unique_ptr<Embedder>> embedders_;
  std::future<Status> running_;
  Status done_;  // start()'s status with one worker
};

// Batches of items through a FramePool: the caller fills a slot, push() counts it, and a full
// batch is embedded while the caller fills the next one; commit() sees the items in the order
// they were pushed, on the caller's thread (what is appended to shared output happens there).
template <class Item>
class BatchPipeline {
 public:
  using Commit = std::function<Status(Item&)>;
  using WorkOn = std::function<Status(Item&, int32_t worker)>;
  BatchPipeline(FramePool& pool, size_t batch, WorkOn work, Commit commit)
      : pool_(pool),
        work_(std::move(work)),
        commit_(std::move(commit)),
        filling_(batch),
        running_(batch) {}
  ~BatchPipeline() {
    if (started_) (void)pool_.wait();
  }

  Item& slot() { return filling_[filled_]; }  // the item the caller fills next
  Status push() { return ++filled_ == filling_.size() ? flush() : Status{}; }
  // Embeds and commits everything pushed so far.
  Status finish() {
    TLV_TRY(flush());
    return drain();
  }

 private:
  Status flush() {
    TLV_TRY(drain());
    if (filled_ == 0) return {};
    std::swap(filling_, running_);
    in_flight_ = filled_;
    filled_ = 0;
    started_ = true;
    pool_.start(in_flight_, [this](size_t i, int32_t w) { return work_(running_[i], w); });
    return {};
  }
  Status drain() {
    if (!started_) return {};
    started_ = false;
    TLV_TRY(pool_.wait());
    for (size_t i = 0; i < in_flight_; ++i) TLV_TRY(commit_(running_[i]));
    return {};
  }

  FramePool& pool_;
  WorkOn work_;
  Commit commit_;
  std::vector<Item> filling_, running_;
  size_t filled_ = 0, in_flight_ = 0;
  bool started_ = false;
};

}  // namespace tlvlink::eval::internal
