// BlockStack (the refiner's queues): last in, first out across block boundaries; the parallel
// refiner's stealing takes the oldest elements in order.
#include "support/block_stack.h"

#include <gtest/gtest.h>

#include <vector>

namespace mesh4d::support {
namespace {

// Beyond two blocks of 4096, so that pushes and pops cross block boundaries.
constexpr int kMany = 10000;

TEST(BlockStack, PopsInReverseOrderAcrossBlocks) {
  BlockStack<int> stack;
  EXPECT_TRUE(stack.empty());
  for (int i = 0; i < kMany; ++i) stack.push_back(i);
  ASSERT_EQ(stack.size(), std::size_t{kMany});
  for (int i = kMany - 1; i >= 0; --i) {
    ASSERT_EQ(stack.back(), i);
    stack.pop_back();
  }
  EXPECT_TRUE(stack.empty());
  // The kept blocks are reused: the same values again after a clear.
  for (int i = 0; i < kMany; ++i) stack.push_back(2 * i);
  stack.clear();
  stack.push_back(7);
  EXPECT_EQ(stack.size(), 1u);
  EXPECT_EQ(stack.back(), 7);
}

TEST(BlockStack, TakesTheBottomInOrderAndKeepsTheRest) {
  BlockStack<int> stack;
  for (int i = 0; i < kMany; ++i) stack.push_back(i);
  std::vector<int> taken;
  stack.take_bottom(kMany / 2 + 1, taken);
  ASSERT_EQ(taken.size(), std::size_t{kMany / 2 + 1});
  for (int i = 0; i < static_cast<int>(taken.size()); ++i) ASSERT_EQ(taken[i], i);
  ASSERT_EQ(stack.size(), std::size_t{kMany - kMany / 2 - 1});
  for (std::size_t i = 0; i < stack.size(); ++i) ASSERT_EQ(stack[i], int(i) + kMany / 2 + 1);
  EXPECT_EQ(stack.back(), kMany - 1);
}

TEST(BlockStack, AssignsAppendsAndCopiesOut) {
  const std::vector<int> a{1, 2, 3}, b{4, 5};
  BlockStack<int> stack;
  for (int i = 0; i < kMany; ++i) stack.push_back(-i);
  stack.assign(a.begin(), a.end());
  stack.append(b.begin(), b.end());
  std::vector<int> out{0};
  stack.copy_to(out);
  EXPECT_EQ(out, (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

}  // namespace
}  // namespace mesh4d::support
