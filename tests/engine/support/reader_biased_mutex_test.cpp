// ReaderBiasedMutex (the feature index's lock): writers exclude readers and each other, readers
// share. Also run under ThreadSanitizer in CI (scripts/test), which reports any unguarded access.
#include "support/reader_biased_mutex.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <shared_mutex>
#include <thread>
#include <vector>

namespace mesh4d::support {
namespace {

TEST(ReaderBiasedMutex, ReadersNeverSeeAHalfWrittenPair) {
  ReaderBiasedMutex mutex;
  long a = 0, b = 0;  // plain: only the mutex orders them
  std::atomic<long> torn{0}, reads{0};
  std::atomic<bool> done{false};
  std::vector<std::thread> threads;
  for (int r = 0; r < 4; ++r)
    threads.emplace_back([&] {
      while (!done.load()) {
        std::shared_lock lock(mutex);
        if (a != b) torn.fetch_add(1);
        reads.fetch_add(1);
      }
    });
  std::vector<std::thread> writers;
  for (int t = 0; t < 2; ++t)
    writers.emplace_back([&] {
      for (int i = 0; i < 2000; ++i) {
        std::lock_guard lock(mutex);
        ++a;
        std::this_thread::yield();  // a reader let in now would see a != b
        ++b;
      }
    });
  for (auto& t : writers) t.join();
  done.store(true);
  for (auto& t : threads) t.join();
  EXPECT_EQ(a, 4000);
  EXPECT_EQ(b, 4000);
  EXPECT_EQ(torn.load(), 0);
  EXPECT_GT(reads.load(), 0);
}

TEST(ReaderBiasedMutex, AReaderWaitsForTheWriterAndReadersShare) {
  ReaderBiasedMutex mutex;
  std::atomic<bool> entered{false};
  mutex.lock();
  std::thread reader([&] {
    std::shared_lock lock(mutex);
    entered.store(true);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(entered.load());
  mutex.unlock();
  reader.join();
  EXPECT_TRUE(entered.load());

  // Two readers at once: the second enters while the first still holds.
  std::shared_lock first(mutex);
  std::atomic<bool> second{false};
  std::thread other([&] {
    std::shared_lock lock(mutex);
    second.store(true);
  });
  other.join();
  EXPECT_TRUE(second.load());
}

}  // namespace
}  // namespace mesh4d::support
