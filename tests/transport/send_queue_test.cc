// The board's bounded queue: FIFO order, drop-oldest, the byte bound, against a reference model
// under seeded random pushes and pops of random sizes (wrap-around included).
#include <gtest/gtest.h>

#include <deque>
#include <vector>

#include "support/random.h"
#include "tlvlink/transport/send_queue.h"

namespace tlvlink::transport {
namespace {

using protocol::MessageType;

std::vector<std::byte> payload(uint32_t id, size_t size) {
  std::vector<std::byte> p(size);
  for (size_t i = 0; i < size; ++i) p[i] = std::byte((id * 31 + i) & 0xFF);
  return p;
}

TEST(SendQueue, FifoAndDropOldest) {
  SendQueue q(4 * SendQueue::record_size(100));
  for (uint32_t i = 0; i < 4; ++i) {
    Result<size_t> d = q.push(MessageType::kFramePrediction, 0, i, payload(i, 100));
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(d.value(), 0u);
  }
  Result<size_t> d = q.push(MessageType::kFramePrediction, 0, 4, payload(4, 100));
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d.value(), 1u);  // the oldest made room
  SendQueue::Record r;
  ASSERT_TRUE(q.front(r));
  EXPECT_EQ(r.enqueue_ns, 1);
  EXPECT_EQ(std::vector<std::byte>(r.payload.begin(), r.payload.end()), payload(1, 100));
  EXPECT_EQ(q.size(), 4u);
  EXPECT_EQ(q.bytes(), 4 * SendQueue::record_size(100));
}

TEST(SendQueue, TooLargeIsRefusedWithoutDropping) {
  SendQueue q(1024);
  ASSERT_TRUE(q.push(MessageType::kStats, 0, 0, payload(0, 10)).ok());
  Result<size_t> d = q.push(MessageType::kStats, 0, 0, payload(1, 2000));
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().code(), ErrorCode::kProtocolTooLarge);
  EXPECT_EQ(q.size(), 1u);
}

TEST(SendQueue, RandomTrafficMatchesAFifoThatDropsOldest) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  for (size_t capacity : {size_t{256}, size_t{1000}, size_t{4096}, size_t{65536}}) {
    SendQueue q(capacity);
    std::deque<std::pair<uint32_t, size_t>> model;  // id, payload size
    uint32_t next_id = 0;
    for (int step = 0; step < 20000; ++step) {
      if (rng.int_in(0, 2) > 0) {
        const size_t size = static_cast<size_t>(rng.int_in(0, static_cast<int>(capacity / 3)));
        if (SendQueue::record_size(size) > q.capacity()) continue;
        const uint32_t id = next_id++;
        Result<size_t> dropped = q.push(MessageType::kFramePrediction,
                                        static_cast<uint16_t>(id & 0xFFFF), id, payload(id, size));
        ASSERT_TRUE(dropped.ok());
        for (size_t k = 0; k < dropped.value(); ++k) model.pop_front();
        model.emplace_back(id, size);
      } else if (!model.empty()) {
        q.pop();
        model.pop_front();
      }
      // The queue holds exactly the newest records of the model, in order, within its bound.
      ASSERT_EQ(q.size(), model.size()) << "step " << step;
      ASSERT_LE(q.bytes(), q.capacity());
      SendQueue::Record r;
      if (!model.empty()) {
        ASSERT_TRUE(q.front(r));
        ASSERT_EQ(r.enqueue_ns, model.front().first);
        ASSERT_EQ(r.payload.size(), model.front().second);
        ASSERT_EQ(std::vector<std::byte>(r.payload.begin(), r.payload.end()),
                  payload(model.front().first, model.front().second));
      }
    }
    // Drain: every record comes out intact and in order.
    SendQueue::Record r;
    while (q.front(r)) {
      ASSERT_EQ(r.enqueue_ns, model.front().first);
      ASSERT_EQ(std::vector<std::byte>(r.payload.begin(), r.payload.end()),
                payload(model.front().first, model.front().second));
      q.pop();
      model.pop_front();
    }
    EXPECT_TRUE(model.empty());
  }
}

TEST(SendQueue, DropOldestNeverTakesMoreThanNeeded) {
  // With equal records, a full queue drops exactly one per push.
  SendQueue q(10 * SendQueue::record_size(48));
  for (uint32_t i = 0; i < 10; ++i)
    ASSERT_EQ(q.push(MessageType::kStats, 0, i, payload(i, 48)).value(), 0u);
  for (uint32_t i = 10; i < 100; ++i)
    ASSERT_EQ(q.push(MessageType::kStats, 0, i, payload(i, 48)).value(), 1u);
  EXPECT_EQ(q.size(), 10u);
}

}  // namespace
}  // namespace tlvlink::transport
