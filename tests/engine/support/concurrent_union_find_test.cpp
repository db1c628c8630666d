// ConcurrentUnionFind (the piece matching's pieces): joined from several threads at once, it
// gives the sets that one thread's UnionFind gives, each rooted at its smallest element. Also
// run under ThreadSanitizer in CI (scripts/test).
#include "support/concurrent_union_find.h"

#include <gtest/gtest.h>

#include <random>
#include <thread>
#include <utility>
#include <vector>

#include "support/union_find.h"

namespace mesh4d::support {
namespace {

TEST(ConcurrentUnionFind, ThreadsGiveTheSetsOfOneThreadRootedAtTheirSmallest) {
  constexpr std::size_t kElements = 200000;
  std::mt19937_64 random(7);
  std::uniform_int_distribution<std::size_t> any(0, kElements - 1);
  std::vector<std::pair<std::size_t, std::size_t>> pairs(150000);
  for (auto& [a, b] : pairs) a = any(random), b = any(random);

  UnionFind reference(kElements);
  for (const auto& [a, b] : pairs) reference.join(a, b);

  for (const unsigned threads : {1u, 2u, 8u}) {
    ConcurrentUnionFind sets(kElements);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
      pool.emplace_back([&, t] {
        for (std::size_t i = t; i < pairs.size(); i += threads)
          sets.join(pairs[i].first, pairs[i].second);
      });
    for (auto& thread : pool) thread.join();

    // Same sets: the reference's root of each set maps to one root here, and back.
    std::vector<std::size_t> smallest(kElements, kElements), mapped(kElements, kElements);
    for (std::size_t i = 0; i < kElements; ++i) {
      const std::size_t r = reference.find(i);
      if (smallest[r] == kElements) smallest[r] = i;  // i ascending: the first is the smallest
    }
    std::size_t wrong_set = 0, wrong_root = 0;
    for (std::size_t i = 0; i < kElements; ++i) {
      const std::size_t root = sets.find(i);
      const std::size_t r = reference.find(i);
      if (mapped[r] == kElements) mapped[r] = root;
      wrong_set += mapped[r] != root;
      wrong_root += root != smallest[r];
    }
    EXPECT_EQ(wrong_set, 0u) << threads << " threads";
    EXPECT_EQ(wrong_root, 0u) << threads << " threads";
  }
}

}  // namespace
}  // namespace mesh4d::support
