// A shared mutex for data read far more often than written: the feature index, read by every
// classification of every worker and written by each R1 insertion.
//
// std::shared_mutex keeps one reader count, so every lock_shared() and unlock_shared() of every
// thread writes the same cache line, and with many threads each one waits for that line to come
// back from another core. Here a reader counts itself in a slot of its own (one per thread,
// threads beyond kSlots share), and a writer raises its flag, then waits until every slot is
// empty. Readers touch only their own line and a flag that changes once per write.
#pragma once

#include <array>
#include <atomic>
#include <mutex>
#include <thread>

namespace mesh4d::support {

class ReaderBiasedMutex {
 public:
  void lock_shared() {
    std::atomic<int>& readers = slot();
    while (true) {
      // Count in, then look for a writer; a writer raises its flag, then looks for readers.
      // Both sequentially consistent, so at least one of the two sees the other.
      readers.fetch_add(1, std::memory_order_seq_cst);
      if (!writer_.load(std::memory_order_seq_cst)) return;
      readers.fetch_sub(1, std::memory_order_release);
      while (writer_.load(std::memory_order_acquire)) std::this_thread::yield();
    }
  }
  void unlock_shared() { slot().fetch_sub(1, std::memory_order_release); }

  void lock() {
    writers_.lock();
    writer_.store(true, std::memory_order_seq_cst);
    for (const Slot& s : slots_)
      while (s.readers.load(std::memory_order_seq_cst) != 0) std::this_thread::yield();
  }
  void unlock() {
    writer_.store(false, std::memory_order_release);
    writers_.unlock();
  }

 private:
  static constexpr unsigned kSlots = 32;
  struct alignas(64) Slot {
    std::atomic<int> readers{0};
  };

  std::atomic<int>& slot() {
    // Threads are numbered on first use, for all instances alike.
    static std::atomic<unsigned> next{0};
    thread_local const unsigned index = next.fetch_add(1, std::memory_order_relaxed) % kSlots;
    return slots_[index].readers;
  }

  std::array<Slot, kSlots> slots_;
  alignas(64) std::atomic<bool> writer_{false};
  std::mutex writers_;
};

}  // namespace mesh4d::support
