// PinchCounts against a plain map under random churn: counts, dropped keys (the table's
// deletion moves later slots back) and the pinched list.
#include "refine/pinch_counts.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

namespace mesh4d::refine {
namespace {

TEST(PinchCounts, MatchesAMapUnderChurn) {
  // Few distinct keys, so that runs of colliding slots form and are deleted from often.
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> vertex(0, 40), label(1, 2);
  std::uniform_int_distribution<int> coin(0, 9);
  PinchCounts counts;
  std::map<PinchKey, int> reference;
  for (int step = 0; step < 200000; ++step) {
    PinchKey key{label(rng), vertex(rng), vertex(rng), vertex(rng)};
    int delta = coin(rng) < 6 ? 1 : -1;
    // Counts never go below 0 here (as in a sequential run).
    if (delta < 0 && reference[key] == 0) delta = 1;
    counts.add(key, delta, static_cast<std::uint32_t>(step));
    if ((reference[key] += delta) == 0) reference.erase(key);
    if (step % 5000 == 0 || step == 199999) {
      std::vector<PinchKey> pinched;
      for (const auto& [k, n] : reference) {
        ASSERT_EQ(counts.count(k), n);
        if (n > 2) pinched.push_back(k);
      }
      ASSERT_EQ(counts.size(), reference.size());
      std::vector<PinchKey> listed;
      for (const auto& p : counts.pinched()) listed.push_back(p.key);
      ASSERT_EQ(listed, pinched);
    }
  }
  EXPECT_EQ(counts.count({9, 1, 2, 3}), 0);
}

TEST(PinchCounts, AKeyBelowZeroForAWhileComesBack) {
  // Parallel workers' logs are applied one worker after the other.
  PinchCounts counts;
  const PinchKey key{1, 4, 5, 6};
  counts.add(key, -1);
  EXPECT_EQ(counts.count(key), -1);
  for (std::uint32_t cell = 10; cell < 14; ++cell) counts.add(key, 1, cell);
  EXPECT_EQ(counts.count(key), 3);
  ASSERT_EQ(counts.pinched().size(), 1u);
  EXPECT_EQ(counts.pinched()[0].key, key);
  // The cell of the change that took it above two.
  EXPECT_EQ(counts.pinched()[0].cell, 13u);
  counts.add(key, -1);
  EXPECT_TRUE(counts.pinched().empty());
  // Above two again: the new cell.
  counts.add(key, 1, 20);
  ASSERT_EQ(counts.pinched().size(), 1u);
  EXPECT_EQ(counts.pinched()[0].cell, 20u);
}

}  // namespace
}  // namespace mesh4d::refine
