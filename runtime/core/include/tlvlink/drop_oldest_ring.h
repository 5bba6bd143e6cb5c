#pragma once
// A bounded FIFO over storage given at construction, never allocating and never blocking: when
// full, push() overwrites the oldest element and counts it (a board keeps the newest data and
// says how much it lost); try_push() refuses the newest instead (for what must not be lost out
// of order, e.g. commands). Not synchronised: its owner locks (one mutex around it serves one or
// many producers and consumers). The ring points into its storage: neither copyable nor movable.

#include <cstddef>
#include <cstdint>
#include <span>

namespace tlvlink {

template <typename T>
class DropOldestRing {
 public:
  explicit DropOldestRing(std::span<T> storage) : slots_(storage) {}
  DropOldestRing(const DropOldestRing&) = delete;
  DropOldestRing& operator=(const DropOldestRing&) = delete;

  // Appends `v`; when full, the oldest element gives way. True when one was dropped.
  bool push(const T& v) {
    if (slots_.empty()) return ++dropped_, true;  // no room at all: `v` itself is lost
    const bool drop = full();
    if (drop) {
      head_ = next(head_);
      --count_;
      ++dropped_;
    }
    slots_[index(count_)] = v;
    ++count_;
    return drop;
  }
  // Appends `v` only when there is room; false (counted in rejected()) when full.
  bool try_push(const T& v) {
    if (full()) {
      ++rejected_;
      return false;
    }
    slots_[index(count_)] = v;
    ++count_;
    return true;
  }
  // Takes the oldest element; false when empty.
  bool pop(T& out) {
    if (count_ == 0) return false;
    out = slots_[head_];
    head_ = next(head_);
    --count_;
    return true;
  }
  const T& front() const { return slots_[head_]; }  // the oldest; only when !empty()
  void clear() { head_ = count_ = 0; }

  size_t size() const { return count_; }
  size_t capacity() const { return slots_.size(); }
  bool empty() const { return count_ == 0; }
  bool full() const { return count_ == slots_.size(); }
  uint64_t dropped() const { return dropped_; }    // oldest elements overwritten by push()
  uint64_t rejected() const { return rejected_; }  // newest elements refused by try_push()

 private:
  size_t next(size_t i) const { return i + 1 == slots_.size() ? 0 : i + 1; }
  size_t index(size_t offset) const {
    const size_t i = head_ + offset;
    return i >= slots_.size() ? i - slots_.size() : i;
  }

  std::span<T> slots_;
  size_t head_ = 0, count_ = 0;
  uint64_t dropped_ = 0, rejected_ = 0;
};

}  // namespace tlvlink
