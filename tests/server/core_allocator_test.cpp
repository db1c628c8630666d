// The cores shared among running jobs as the queue changes (core_allocator.h): all to a lone
// job; fewer per job as jobs queue, the running ones' budgets included; back as jobs end.
#include "core_allocator.h"

#include <gtest/gtest.h>

namespace mesh4d::server {
namespace {

TEST(CoreAllocator, ALoneJobGetsEveryCore) {
  CoreAllocator cores(16, 16, 16);
  const auto job = cores.start(0, 0);
  EXPECT_EQ(job.threads, 16u);
  EXPECT_EQ(job.budget->limit(), 16u);
}

// A burst: the first job starts alone with every core; as the others queue and start it keeps
// one core, and the later ones start with one thread. As they end, it gets its cores back.
TEST(CoreAllocator, ABurstSharesTheCoresAndTheFirstJobGetsThemBack) {
  CoreAllocator cores(16, 16, 16);
  const auto first = cores.start(0, 0);
  cores.queue_changed(17);
  EXPECT_EQ(first.budget->limit(), 1u);
  std::vector<CoreAllocator::Share> others;
  for (int i = 0; i < 15; ++i) others.push_back(cores.start(0, 16 - i));
  for (const auto& s : others) EXPECT_EQ(s.threads, 1u);
  EXPECT_EQ(first.budget->limit(), 1u);
  for (std::size_t i = 0; i < others.size(); ++i) cores.finish(others[i], 0);
  EXPECT_EQ(first.budget->limit(), 16u);
}

// 16 cores, two jobs: the one that asked for 3 threads keeps 3; the other gets the 13 left.
TEST(CoreAllocator, AJobThatCannotUseItsShareLeavesItToTheOthers) {
  CoreAllocator cores(16, 16, 16);
  const auto big = cores.start(0, 0);
  const auto small = cores.start(3, 0);
  EXPECT_EQ(small.threads, 3u);
  EXPECT_EQ(small.budget->limit(), 3u);
  EXPECT_EQ(big.budget->limit(), 13u);
  const auto third = cores.start(0, 0);  // 13 over two: 6 and 7
  EXPECT_EQ(third.budget->limit() + big.budget->limit(), 13u);
  EXPECT_EQ(small.budget->limit(), 3u);
}

// The caps: at most 4 threads a job; at most 2 jobs at once (the waiting ones beyond the free
// runners do not shrink the running ones).
TEST(CoreAllocator, TheCapsHold) {
  CoreAllocator per_job(16, 4, 16);
  EXPECT_EQ(per_job.start(0, 0).threads, 4u);
  CoreAllocator two_runners(16, 16, 2);
  const auto a = two_runners.start(0, 0);
  two_runners.queue_changed(10);
  EXPECT_EQ(a.budget->limit(), 8u);
  const auto b = two_runners.start(0, 9);
  EXPECT_EQ(b.threads, 8u);
  EXPECT_EQ(a.budget->limit(), 8u);
}

}  // namespace
}  // namespace mesh4d::server
